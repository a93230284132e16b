#!/usr/bin/env python3
"""Why a long exploration goes on: what each goal found and what changed between map snapshots.

Runs one in-process collection episode (the settings of ``--settings``, default
config/fidelity/seed_study.yaml) of one building with one seed, stepping the same closed loop
and stop rule as :func:`slam_predict.collect.episode.explore_until_stop`, and reports

- per explorer goal: sim time sent/ended, outcome, distance driven for it (m, ground truth),
  coverage of the reachable floor when it ended and what the goal added;
- per map snapshot: sim time, distance so far, coverage, the MSE to the previous snapshot and
  its three parts, each as MSE over the whole image: ``new`` (unknown in the previous snapshot,
  known in this one), ``lost`` (known → unknown) and ``changed`` (known in both, another grey
  level: walls and free space that GMapping's map moved);
- totals: the distance driven after coverage first reached 0.95 / 0.98 and by goals that added
  less than 0.1 % coverage.

    python bench/bench_exploration_diagnostics.py Neulengbach1_updated --seed 1669048120
    python bench/bench_exploration_diagnostics.py lab_intel --seed 7 --json out/diag.json
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench"))
sys.path.insert(0, str(ROOT / "src"))

from bench_no_behaviour_change import world_path  # noqa: E402

from slam_predict.collect.episode import Recorder, full_extent_grid  # noqa: E402
from slam_predict.collect.settings import load_settings  # noqa: E402
from slam_predict.collect.stopping import SnapshotMSE, grid_to_snapshot, stop_reason  # noqa: E402
from slam_predict.explore.coverage import coverage, reachable_free  # noqa: E402
from slam_predict.explore.loop import ClosedLoop  # noqa: E402
from slam_predict.formats.mapserver import UNKNOWN  # noqa: E402
from slam_predict.nav.costmap import inscribed_radius  # noqa: E402
from slam_predict.world.load import load_plan  # noqa: E402

LOW_GAIN = 0.001   # coverage share: a goal adding less found (almost) nothing


def mse_parts(a: np.ndarray, b: np.ndarray) -> dict[str, float]:
    """The snapshot MSE of ``a`` → ``b`` split by pixel class (each over the whole image)."""
    sq = np.square(a.astype(np.int64) - b.astype(np.int64))
    was, now = a != UNKNOWN, b != UNKNOWN
    size = float(a.size)
    return {"total": float(sq.sum()) / size,
            "new": float(sq[~was & now].sum()) / size,
            "lost": float(sq[was & ~now].sum()) / size,
            "changed": float(sq[was & now].sum()) / size}


class Diagnostics:
    """Goal and snapshot records of one run."""

    def __init__(self, world, loop, settings):
        self.world, self.loop = world, loop
        self.reach = reachable_free(world, inscribed_radius(settings.nav.global_costmap))
        self.goals: list[dict] = []
        self.snapshots: list[dict] = []
        self._goals_seen = 0
        self._cov_before = 0.0
        self._dist_before = 0.0

    def coverage_now(self) -> float:
        grid = self.loop.source.map()
        return 0.0 if grid is None else coverage(self.world, grid, self.reach,
                                                 self.loop.world_T_map)

    def after_step(self) -> None:
        goals = self.loop.explorer.log.goals
        while self._goals_seen < len(goals):
            goal = goals[self._goals_seen]
            self._goals_seen += 1
            cov, dist = self.coverage_now(), self.loop.log.distance_m
            self.goals.append({**goal, "distance_m": dist - self._dist_before,
                               "coverage": cov, "gain": cov - self._cov_before})
            self._cov_before, self._dist_before = cov, dist

    def snapshot(self, t: float, previous, current) -> None:
        parts = mse_parts(previous, current) if previous is not None else None
        self.snapshots.append({"t": t, "distance_m": self.loop.log.distance_m,
                               "coverage": self.coverage_now(), "mse": parts})


def run(world_name: str, seed: int, settings_file: str, max_sim: float) -> dict:
    settings = load_settings(settings_file)
    world = load_plan(str(world_path(ROOT, world_name)))
    loop = ClosedLoop(world, seed, settings.nav, settings.explore, settings.sim,
                      map_source=settings.slam.type, slam_params=settings.slam.params,
                      compute=settings.compute)
    diag = Diagnostics(world, loop, settings)
    rule = SnapshotMSE(settings.stop, settings.stop.interval_for(world.free_area_m2))
    recorder = Recorder()
    while True:
        loop.step()
        recorder.add(loop)
        diag.after_step()
        if rule.due(loop.t) and loop.grid is not None:
            snap = grid_to_snapshot(full_extent_grid(loop.source.map(), loop.source.map_extent))
            diag.snapshot(loop.t, rule.last, snap)
            rule.add(loop.t, snap)
        reason = stop_reason(settings.stop, rule, loop.t, 0.0) or (
            "max_sim" if loop.t >= max_sim else None)
        if reason:
            break
    return {"world": world_name, "seed": seed, "settings": settings_file, "stop": reason,
            "t": loop.t, "distance_m": loop.log.distance_m, "coverage": diag.coverage_now(),
            "explorer_stop": loop.explorer.log.stop_reason, "goals": diag.goals,
            "stuck": recorder.stuck.record(settings.stop),
            "snapshots": diag.snapshots}


def distance_after(goals: list[dict], level: float) -> float:
    """Distance (m) driven by the goals that ended after coverage first reached ``level``."""
    reached = [k for k, g in enumerate(goals) if g["coverage"] >= level]
    return sum(g["distance_m"] for g in goals[reached[0] + 1:]) if reached else 0.0


def report(result: dict) -> str:
    goals = result["goals"]
    lines = [f"{result['world']} seed {result['seed']}: {result['stop']} at {result['t']:.0f} s, "
             f"{result['distance_m']:.0f} m, coverage {result['coverage']:.3f}, explorer "
             f"{result['explorer_stop']}, {len(goals)} goals, longest still while exploring "
             f"{result['stuck']['longest_still_s']:.0f} s",
             "snapshot  t s  dist m  coverage   mse   new  lost  changed"]
    for s in result["snapshots"]:
        m = s["mse"] or {"total": float("nan"), "new": float("nan"), "lost": float("nan"),
                         "changed": float("nan")}
        lines.append(f"  {s['t']:6.0f} {s['distance_m']:7.0f} {s['coverage']:9.3f} "
                     f"{m['total']:6.1f} {m['new']:5.1f} {m['lost']:5.1f} {m['changed']:7.1f}")
    low = [g for g in goals if g["gain"] < LOW_GAIN]
    outcomes: dict[str, int] = {}
    for g in goals:
        outcomes[g["outcome"]] = outcomes.get(g["outcome"], 0) + 1
    lines += [f"goals by outcome: {outcomes}",
              f"goals adding < {LOW_GAIN:.1%} coverage: {len(low)} of {len(goals)}, "
              f"{sum(g['distance_m'] for g in low):.0f} m of {result['distance_m']:.0f} m",
              f"distance after coverage 0.95: {distance_after(goals, 0.95):.0f} m, "
              f"after 0.98: {distance_after(goals, 0.98):.0f} m"]
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("world", help="shipped world name or seed-study building (imported)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--settings", default="config/fidelity/seed_study.yaml")
    ap.add_argument("--max-sim-time", type=float, default=14400.0, help="s")
    ap.add_argument("--json", help="write the goal and snapshot records here")
    args = ap.parse_args(argv)
    result = run(args.world, args.seed, args.settings, args.max_sim_time)
    print(report(result))
    if args.json:
        Path(args.json).write_text(json.dumps(result, indent=1, default=float))
    return 0


if __name__ == "__main__":
    sys.exit(main())
