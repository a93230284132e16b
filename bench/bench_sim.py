#!/usr/bin/env python3
"""Benchmark the simulator: one 541-beam scan at 30 m, one full step, ROS message building.

Targets (issue 3): scan ≤ 0.3 ms on the largest shipped world; full step ≤ 1 ms.
World: the largest ``worlds/*.world`` (by free area) if any, else the largest ipa floor plan in
../shared/data at 0.05 m/px, else a synthetic 80 m × 50 m office. Prints one line per figure.
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
os.environ.setdefault("NUMBA_CACHE_DIR", str(ROOT / ".numba_cache"))

from slam_predict.sim import LaserOverrides, SimConfig, Simulator  # noqa: E402
from slam_predict.sim.raycast import LaserGrid  # noqa: E402
from slam_predict.world.model import World  # noqa: E402
from slam_predict.world.start import default_start  # noqa: E402


def largest_world() -> tuple:
    """(World, description) of the benchmark world."""
    worlds = sorted((ROOT / "worlds").glob("*.world"))
    if worlds:
        from slam_predict.world.load import load_plan

        loaded = [load_plan(p) for p in worlds]
        best = max(loaded, key=lambda w: w.free_area_m2)
        return best, f"shipped {best.name}"
    shared = Path(os.environ.get("SLAM_PREDICT_SHARED", ROOT.parent / "shared"))
    plans = sorted((shared / "data" / "floorplans" / "ipa").glob("*.png"))
    plans = [p for p in plans if "_gt_" not in p.name]
    if plans:
        from slam_predict.world.bitmap import load_occupancy

        loaded = [(p.stem, load_occupancy(p)) for p in plans]
        name, occ = max(loaded, key=lambda item: int((~item[1]).sum()))
        return World(name, occ, 0.05), f"ipa {name} at 0.05 m/px (largest free area)"
    occ = np.zeros((1000, 1600), bool)
    occ[:3], occ[-3:], occ[:, :3], occ[:, -3:] = True, True, True, True
    occ[::100, :] = True
    occ[:, ::160] = True
    occ[::100, 40:80] = False
    occ[40:60, ::160] = False
    return World("synthetic", occ, 0.05), "synthetic 80 x 50 m office"


def free_poses(world: World, n: int, rng) -> np.ndarray:
    rows, cols = np.nonzero(~world.occupied)
    pick = rng.integers(0, rows.size, n)
    xy = world.cell_to_world(np.stack([rows[pick], cols[pick]], axis=1))
    return np.column_stack([xy, rng.uniform(-np.pi, np.pi, n)])


def best_of(fn, repeats: int, count: int) -> tuple:
    """(wall ms, CPU ms) per item, best of ``repeats`` runs of ``fn`` doing ``count`` items.

    The machine is shared, so the CPU time of this process is reported next to wall time.
    """
    wall = cpu = float("inf")
    for _ in range(repeats):
        w0, c0 = time.perf_counter(), time.process_time()
        fn()
        wall = min(wall, (time.perf_counter() - w0) / count * 1e3)
        cpu = min(cpu, (time.process_time() - c0) / count * 1e3)
    return wall, cpu


def bench_scan(world: World, poses: np.ndarray, repeats: int) -> tuple:
    """(wall, CPU) ms per 541-beam scan at range_max 30 m, and the mean range (m)."""
    grid = LaserGrid.of_world(world)
    angles = np.deg2rad(np.linspace(-135, 135, 541))
    cos_a, sin_a = np.cos(angles), np.sin(angles)
    out = np.empty(541, np.float32)
    grid.scan(*poses[0], cos_a, sin_a, 30.0, out)
    ranges = []

    def run():
        ranges.clear()
        for x, y, yaw in poses:
            ranges.append(grid.scan(x, y, yaw, cos_a, sin_a, 30.0, out).mean())

    wall, cpu = best_of(run, repeats, len(poses))
    return wall, cpu, float(np.mean(ranges))


def wander(sim: Simulator, steps: int, commands: list) -> int:
    """Drive around reacting to the scan (forward; turn in place towards the freer side when
    something is within 0.7 m ahead); records the commands. Returns the number of stalls."""
    stalled = 0
    v, w = 0.8, 0.0
    front = np.abs(sim.laser_angles) < 0.6
    left = sim.laser_angles > 0
    for _ in range(steps):
        state = sim.step(v, w)
        commands.append((v, w))
        stalled += state.stalled
        ranges = state.scan
        if ranges[front].min() < 0.7 or state.stalled:
            turn = 1.0 if ranges[left].mean() > ranges[~left].mean() else -1.0
            v, w = 0.0, (w if v == 0.0 and w != 0.0 else turn)
        else:
            v, w = 0.8, 0.0
    return stalled


def replay(sim: Simulator, commands: list) -> None:
    for v, w in commands:
        sim.step(v, w)


def bench_steps(world: World, start: np.ndarray, steps: int, repeats: int) -> tuple:
    """(wall, CPU) ms per full step with a scan at 30 m, CPU ms without scan, stall share."""
    placed = world.replace(start_pose=start)
    config = SimConfig(laser=LaserOverrides(range_max=30.0))
    commands: list = []
    stalls = wander(Simulator(placed, config, np.random.default_rng(0)), steps, commands)
    quiet = SimConfig(laser=LaserOverrides(rate_hz=1e-6))
    wall, cpu = best_of(lambda: replay(Simulator(placed, config, np.random.default_rng(0)),
                                       commands), repeats, steps)
    _, cpu_quiet = best_of(lambda: replay(Simulator(placed, quiet, np.random.default_rng(0)),
                                          commands), repeats, steps)
    return wall, cpu, cpu_quiet, stalls / steps


def bench_ros_step(world: World, start: np.ndarray, steps: int) -> float:
    """ms per stage_sim step including building + serialising its messages (no transport)."""
    try:
        import io

        from slam_predict.ros.stage_sim_node import StageSim
        from slam_predict.ros.stage_sim_params import NodeSettings
    except ImportError:
        return float("nan")

    class Sink:
        def publish(self, msg):
            msg.serialize(io.BytesIO())

        def sendTransform(self, transforms):  # noqa: N802
            for t in transforms:
                t.serialize(io.BytesIO())

    sim = Simulator(world.replace(start_pose=start), SimConfig(), np.random.default_rng(0))
    node = StageSim(sim, NodeSettings(), None)
    node._pubs = {k: Sink() for k in ("clock", "odom", "truth", "scan")}
    node._tf = Sink()
    node._command = (0.3, 0.2)
    node._last_command_t = float("inf")
    node.settings.watchdog_timeout = 0.0
    node.step()
    t0 = time.perf_counter()
    for _ in range(steps):
        node.step()
    return (time.perf_counter() - t0) / steps * 1e3


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--poses", type=int, default=500)
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    world, what = largest_world()
    rows, cols = world.shape
    print(f"world: {what}, {cols} x {rows} cells, {world.free_area_m2:.0f} m² free")
    poses = free_poses(world, args.poses, rng)
    wall, cpu, mean_range = bench_scan(world, poses, args.repeats)
    print(f"scan (541 beams, range_max 30 m, mean range {mean_range:.1f} m): "
          f"{cpu:.3f} ms CPU, {wall:.3f} ms wall   [target ≤ 0.3 ms]")
    start = default_start(world)  # the free cell of largest clearance
    wall, cpu, cpu_quiet, stalled = bench_steps(world, start, args.steps, args.repeats)
    print(f"full step (command, kinematics, odometry, collision, scan): {cpu:.3f} ms CPU, "
          f"{wall:.3f} ms wall   [target ≤ 1 ms] (stalled {stalled:.0%} of steps)")
    print(f"step without a scan: {cpu_quiet:.3f} ms CPU; with scans {1e3 / cpu:.0f} steps/s = "
          f"{100 / cpu:.0f}x real time at interval_sim 0.1 s")
    ros = bench_ros_step(world, start, min(args.steps, 1000))
    print(f"stage_sim step incl. building + serialising its ROS messages: {ros:.3f} ms wall")
    return 0


if __name__ == "__main__":
    sys.exit(main())
