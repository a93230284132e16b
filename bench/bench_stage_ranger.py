#!/usr/bin/env python3
"""Benchmark the Stage ranger model against the exact caster on Stage .world files.

For each world: the scan time (ms, mean of the poses, after a warm-up scan) of both ranger
models with config/robot.yaml's laser, and the distribution of stage − exact range differences
over beams hitting something in both (median, IQR, std, share differing by more than one Stage
cell), overall, for the central 90 % of beams ("core", corners and grazing beams dropped) and by
the world direction the beam points to (±x, ±y within 30°). Poses: ``--poses`` random free
poses (seeded) where the robot's footprint fits.

Usage: bench/bench_stage_ranger.py WORLD.world [...] [--poses 30] [--seed 0]
(thesis worlds: ``slam-predict worlds import-thesis ../shared/data/thesis/environments.csv
--out DIR``).
"""
from __future__ import annotations

import argparse
import dataclasses
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
os.environ.setdefault("NUMBA_CACHE_DIR", str(ROOT / ".numba_cache"))

from slam_predict.config import load_config  # noqa: E402
from slam_predict.sim import LaserOverrides, SimConfig, Simulator  # noqa: E402
from slam_predict.world.load import load_plan  # noqa: E402


def free_poses(sim: Simulator, n: int, rng) -> np.ndarray:
    """``n`` poses on free cells where the footprint does not collide."""
    world = sim.world
    rows, cols = np.nonzero(~world.occupied)
    out = []
    while len(out) < n:
        i = rng.integers(0, rows.size)
        x, y = world.cell_to_world(np.array([rows[i], cols[i]]))
        pose = np.array([x, y, rng.uniform(-math.pi, math.pi)])
        if not sim.collides(pose):
            out.append(pose)
    return np.array(out)


def timed_scans(sim: Simulator, poses: np.ndarray) -> tuple[np.ndarray, float]:
    """Ranges (poses × beams) and the mean scan time in ms."""
    sim.scan_from(poses[0])
    start = time.perf_counter()
    scans = np.array([sim.scan_from(p) for p in poses], dtype=float)
    return scans, 1000.0 * (time.perf_counter() - start) / len(poses)


def stats(d: np.ndarray, cell: float) -> str:
    if d.size == 0:
        return "no beams"
    q1, med, q3 = np.percentile(d, [25, 50, 75])
    return (f"n {d.size:6d}  median {med:+.4f}  IQR [{q1:+.4f}, {q3:+.4f}]  std {d.std():.4f}"
            f"  >1 cell {100.0 * np.mean(np.abs(d) > cell + 1e-6):5.1f} %")


def bench_world(path: str, config: SimConfig, n: int, seed: int) -> None:
    world = load_plan(path)
    exact = Simulator(world, config, np.random.default_rng(seed))
    stage = Simulator(world, dataclasses.replace(config, ranger_model="stage"),
                      np.random.default_rng(seed))
    cell = stage.stage_grid.resolution
    poses = free_poses(exact, n, np.random.default_rng(seed))
    e, t_exact = timed_scans(exact, poses)
    s, t_stage = timed_scans(stage, poses)
    rmax = exact.laser.range_max
    hit = (e < rmax) & (s < rmax)
    d = s - e
    yaw = np.array([exact.laser_world_pose(p)[2] for p in poses])
    bearing = yaw[:, None] + exact.laser_angles[None, :]
    core = np.abs(d) <= np.percentile(np.abs(d[hit]), 90)
    print(f"{world.name}: {world.shape[1]}x{world.shape[0]} px at {world.resolution} m/px, "
          f"Stage cell {cell} m, {n} poses, {exact.laser.samples} beams")
    print(f"  scan time: exact {t_exact:.2f} ms, stage {t_stage:.2f} ms")
    print(f"  all  {stats(d[hit], cell)}")
    print(f"  core {stats(d[hit & core], cell)}")
    for name, angle in (("+x", 0.0), ("+y", math.pi / 2), ("-x", math.pi), ("-y", -math.pi / 2)):
        facing = np.cos(bearing - angle) > math.cos(math.radians(30.0))
        print(f"  {name}   {stats(d[hit & facing], cell)}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("worlds", nargs="+", metavar="WORLD")
    parser.add_argument("--poses", type=int, default=30)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    config = load_config(SimConfig, ROOT / "config" / "robot.yaml", "sim")
    config = dataclasses.replace(config, laser=dataclasses.replace(config.laser, noise_std=0.0))
    assert isinstance(config.laser, LaserOverrides)
    for path in args.worlds:
        bench_world(path, config, args.poses, args.seed)
    return 0


if __name__ == "__main__":
    sys.exit(main())
