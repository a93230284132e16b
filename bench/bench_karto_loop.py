#!/usr/bin/env python3
"""Where the SLAM error of a closed-loop episode comes from: the pose error against ground truth
over time, the scans the back-end processed, its scan-matching responses and loop closures, and
the goals of the explorer with the robot's progress.

Runs one in-process episode (settings of ``--settings``, default config/collect_karto.yaml; the
same loop and stop rule as :func:`slam_predict.collect.episode.explore_until_stop`), then prints

- the absolute SLAM position error |world_T_map ⊕ slam − gt| (m) and heading error (rad) every
  ``--every`` sim s, with the scans processed and loop closures so far;
- the largest jumps of the error between consecutive steps (with the loop closures near them);
- per explorer goal: sent/end time, outcome, target, robot (gt) at its end;
- Karto only: matcher responses (quantiles) of the sequential matches.

``--out DIR`` keeps the per-step arrays (steps.npz) and the final SLAM map (map.npy, map.json).

    nice python bench/bench_karto_loop.py office_1500 --seed 12345 --max-sim-time 900
    nice python bench/bench_karto_loop.py office_500 --settings config/collect.yaml
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from slam_predict.collect.episode import Recorder, full_extent_grid  # noqa: E402
from slam_predict.collect.record import measure  # noqa: E402
from slam_predict.collect.settings import load_settings  # noqa: E402
from slam_predict.collect.stopping import SnapshotMSE, grid_to_snapshot, stop_reason  # noqa: E402
from slam_predict.explore.loop import ClosedLoop  # noqa: E402
from slam_predict.world.load import load_plan  # noqa: E402


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("world", help="shipped world name (worlds/NAME.world)")
    parser.add_argument("--settings", default="config/collect_karto.yaml")
    parser.add_argument("--seed", type=int, default=12345)
    parser.add_argument("--max-sim-time", type=float, default=900.0)
    parser.add_argument("--every", type=float, default=50.0, help="sim s between error rows")
    parser.add_argument("--out", type=Path, help="folder for steps.npz and the final map")
    parser.add_argument("--no-map-thread", action="store_true",
                        help="publish the map only with a processed scan (as before the map "
                             "thread: the loop of commit 6426704)")
    return parser.parse_args(argv)


def watch_matcher(loop) -> list[tuple[float, float]]:
    """(sim s, response) of every sequential Karto match (empty for other back-ends)."""
    responses: list[tuple[float, float]] = []
    mapper = getattr(loop.source, "mapper", None)
    if mapper is None:
        return responses
    match = mapper.matcher.match

    def recording(scan, base, *args, **kwargs):
        out = match(scan, base, *args, **kwargs)
        responses.append((loop.t, float(out[0])))
        return out

    mapper.matcher.match = recording
    return responses


def run(loop, settings, free_area_m2: float):
    """Step the loop to its stop; per step: processed scans and loop closures so far."""
    rule = SnapshotMSE(settings.stop, settings.stop.interval_for(free_area_m2))
    recorder = Recorder()
    counts = []
    while True:
        loop.step()
        recorder.add(loop)
        stats = getattr(loop.source, "stats", dict)()
        counts.append((stats.get("scans_processed", 0), len(stats.get("loop_closures", []))))
        if rule.due(loop.t) and loop.grid is not None:
            rule.add(loop.t, grid_to_snapshot(full_extent_grid(loop.source.map(),
                                                               loop.source.map_extent)))
        reason = stop_reason(settings.stop, rule, recorder.stuck, loop.t, 0.0,
                             not loop.explorer.done)
        if reason:
            return reason, recorder, np.asarray(counts)


def errors(loop, recorder):
    """(t, position error m, heading error rad) of every step, SLAM pose in the world frame."""
    from slam_predict.geometry import compose, wrap_angle

    traj = recorder.trajectories()
    slam_world = np.array([compose(loop.world_T_map, p) for p in traj.slam])
    pos = np.hypot(*(slam_world[:, :2] - traj.ground_truth[:, :2]).T)
    head = np.abs(wrap_angle(slam_world[:, 2] - traj.ground_truth[:, 2]))
    return traj, pos, head


def report(loop, reason, traj, pos, head, counts, responses, cpu_s):
    metric = measure(traj, SETTINGS, ARGS.seed)
    print(f"stop {reason} at {loop.t:.0f} s, distance {loop.log.distance_m:.0f} m, "
          f"CPU {cpu_s:.1f} s, trans_mean {metric['trans_mean']:.4f} m, "
          f"rot_mean {metric['rot_mean']:.4f} rad")
    print(f"{'t s':>6}{'pos err m':>10}{'head err':>9}{'scans':>7}{'closures':>9}")
    every = max(1, int(round(ARGS.every / max(traj.t[1] - traj.t[0], 1e-3))))
    for i in list(range(0, len(traj.t), every)) + [len(traj.t) - 1]:
        print(f"{traj.t[i]:>6.0f}{pos[i]:>10.3f}{head[i]:>9.3f}{counts[i, 0]:>7d}"
              f"{counts[i, 1]:>9d}")
    jumps = np.abs(np.diff(pos))
    print("largest error jumps (t, Δ m, closures before → after):")
    for i in np.argsort(jumps)[::-1][:8]:
        print(f"  {traj.t[i + 1]:7.1f} {pos[i + 1] - pos[i]:+.3f}  {counts[i, 1]} → "
              f"{counts[i + 1, 1]}")
    if responses:
        r = np.array([x[1] for x in responses])
        print(f"sequential matches {len(r)}: response quantiles 5/25/50/75/95 % "
              f"{np.round(np.quantile(r, [0.05, 0.25, 0.5, 0.75, 0.95]), 3).tolist()}, "
              f"< 0.1: {int(np.sum(r < 0.1))}")
    print("goals (t sent, t end, outcome, target, gt at end):")
    for g in loop.explorer.log.goals:
        t_end = g.get("t_end", g.get("t"))
        idx = min(np.searchsorted(traj.t, t_end or 0.0), len(traj.t) - 1)
        gt = traj.ground_truth[idx]
        slim = {k: (round(v, 2) if isinstance(v, float) else v) for k, v in g.items()
                if k in ("t_sent", "t_start", "t_end", "outcome", "goal", "target")}
        print(f"  {json.dumps(slim, default=str)}  gt ({gt[0]:.2f}, {gt[1]:.2f})")


def end_state(loop) -> None:
    """What the explorer and the navigator do when the run ends."""
    ex, nav = loop.explorer, loop.navigator
    goal = getattr(ex, "goal", None)
    print(f"end: explorer goal {None if goal is None else np.round(goal.target, 2).tolist()}, "
          f"frontiers {len(getattr(ex, 'frontiers', []) or [])}, "
          f"recently visited {len(getattr(ex, 'recent', []))}, "
          f"blacklist {len(getattr(ex, 'blacklist', []))}; navigator state "
          f"{getattr(nav, 'state', None)}, goal {getattr(nav.goal, 'target', None)}; "
          f"last map published at {loop._last_map_t:.1f} s")
    cmds = np.array(loop.log.commands[-3000:]) if loop.log.commands else np.zeros((0, 3))
    if len(cmds):
        moving = np.abs(cmds[:, 1]) + np.abs(cmds[:, 2]) > 1e-6
        print(f"last {cmds[-1, 0] - cmds[0, 0]:.0f} s of commands: {int(moving.sum())} of "
              f"{len(cmds)} non-zero, mean |v| {np.mean(np.abs(cmds[:, 1])):.3f} m/s")


def save(out: Path, loop, traj, pos, head, counts, responses):
    out.mkdir(parents=True, exist_ok=True)
    np.savez(out / "steps.npz", t=traj.t, gt=traj.ground_truth, slam=traj.slam,
             odom=traj.odom, pos=pos, head=head, counts=counts,
             responses=np.asarray(responses, float).reshape(-1, 2))
    grid = loop.source.map()
    np.save(out / "map.npy", grid.data)
    (out / "map.json").write_text(json.dumps({
        "resolution": float(grid.resolution), "origin": [float(v) for v in grid.origin[:2]],
        "world_T_map": loop.world_T_map.tolist(),
        "goals": loop.explorer.log.goals, "stats": {
            k: v for k, v in getattr(loop.source, "stats", dict)().items()
            if k != "accepted_input_indices"}}, default=str))


def main(argv) -> int:
    global ARGS, SETTINGS
    ARGS = parse_args(argv)
    settings = SETTINGS = load_settings(str(ROOT / ARGS.settings))
    world = load_plan(ROOT / "worlds" / f"{ARGS.world}.world")
    settings.stop = dataclasses.replace(settings.stop, max_sim_time_s=ARGS.max_sim_time)
    loop = ClosedLoop(world, ARGS.seed, settings.nav, settings.explore, settings.sim,
                      map_source=settings.slam.type, slam_params=settings.slam.params,
                      compute=settings.compute)
    if ARGS.no_map_thread:
        loop._map_thread = False
    responses = watch_matcher(loop)
    cpu0 = time.process_time()
    reason, recorder, counts = run(loop, settings, world.free_area_m2)
    cpu = time.process_time() - cpu0
    traj, pos, head = errors(loop, recorder)
    if ARGS.out:
        save(ARGS.out, loop, traj, pos, head, counts, responses)
    report(loop, reason, traj, pos, head, counts, responses, cpu)
    end_state(loop)
    return 0


ARGS = argparse.Namespace()
SETTINGS = None

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
