"""Closed-loop exploration benchmark: wall time of one exploration with the perfect map source,
and the share of it spent in each component.

Runs ``explore_world`` (simulator + perfect map + move_base equivalent + explorer, sim time, no
ROS) on each plan (default: the shipped office_1500) and prints: sim time (the thesis reports
20–40 min of simulated time for a 1,500 m² office, its Table 4.1), wall and CPU time, distance,
coverage, stalls, stop reason, the share of wall time per component (simulator, map source,
explorer, navigator) and, inside the navigator, per kernel (rollouts, BFS distance grids,
inflation, grid search) measured with wrappers around them.

Usage: bench/bench_explore.py [PLAN ...] [--seed N] [--max-sim-time S] [--resolution R]
"""
from __future__ import annotations

import argparse
import functools
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from slam_predict.explore import run as runner  # noqa: E402
from slam_predict.nav import kernels, rollout  # noqa: E402
from slam_predict.warmup import warm_all  # noqa: E402
from slam_predict.world.load import load_plan  # noqa: E402

KERNELS = ((rollout, "score_samples", "rollouts"), (kernels, "target_distance", "BFS grids"),
           (kernels, "inflate", "inflation"), (kernels, "grid_search", "global planner search"))


def instrument(totals):
    """Wrap the navigation kernels to accumulate their wall time in ``totals``."""
    for module, name, label in KERNELS:
        original = getattr(module, name)

        @functools.wraps(original)
        def timed(*args, _f=original, _label=label, **kwargs):
            start = time.perf_counter()
            try:
                return _f(*args, **kwargs)
            finally:
                totals[_label] = totals.get(_label, 0.0) + time.perf_counter() - start
        setattr(module, name, timed)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("plans", nargs="*", default=[str(ROOT / "worlds" / "office_1500.world")])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--max-sim-time", type=float, default=10800.0)
    parser.add_argument("--resolution", type=float)
    args = parser.parse_args()
    warm_all()
    settings = runner.load_settings(ROOT / "config")
    totals = {}
    instrument(totals)
    for plan in args.plans:
        totals.clear()
        world = load_plan(plan, resolution=args.resolution)
        cpu = time.process_time()
        summary, loop = runner.explore_world(world, args.seed, settings,
                                             max_sim_time=args.max_sim_time)
        cpu = time.process_time() - cpu
        wall = summary["wall_time_s"]
        print(f"== {world.name} ({(~world.occupied).sum() * world.resolution ** 2:.0f} m² free), "
              f"seed {args.seed}")
        print(f"sim time {summary['sim_time_s'] / 60:.1f} min (thesis, 1,500 m² office: 20–40 "
              f"min) | wall {wall:.1f} s | CPU {cpu:.1f} s | "
              f"{1000 * wall / max(1, len(loop.log.t)):.1f} ms/step")
        print(f"coverage {summary['coverage']:.3f} | distance {summary['distance_m']:.0f} m | "
              f"stalls {summary['stalls']} | stop {summary['stop_reason']} | goals "
              f"{summary['explorer_goals']}")
        for name, seconds in sorted(summary["timing_s"].items(), key=lambda kv: -kv[1]):
            print(f"  {name:<12} {seconds:8.1f} s  {100 * seconds / wall:5.1f} %")
        for name, seconds in sorted(totals.items(), key=lambda kv: -kv[1]):
            print(f"    navigator kernel {name:<22} {seconds:8.1f} s  {100 * seconds / wall:5.1f} %")
    return 0


if __name__ == "__main__":
    sys.exit(main())
