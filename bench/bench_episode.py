"""Episode speed benchmark (issue #7): one in-process collection episode, as `slam-predict
collect` runs it, with the wall time split per component.

Runs :func:`slam_predict.collect.episode.run_episode` on WORLD (default: the shipped
office_1500, 40 particles, 541 beams, config/collect.yaml) and prints the sim time, wall and
process CPU time, the ratios sim/wall and sim/CPU, the stop reason and the exclusive wall time
of each component: simulator, GMapping scan processing, published-map rebuild (loop / snapshots),
costmaps (map + scan input, updates), global planner, local planner, explorer (frontiers),
snapshots + stop rule, recording, and the rest (episode bookkeeping, metric, writing). Timers
wrap the components' methods; a timer inside another one is subtracted from the outer one.
``--profile`` runs cProfile instead of the timers and prints the top functions;
``--rebuild-map`` rebuilds the published map from scratch at every update (as before issue #7)
instead of updating it incrementally (same results, for the before/after figure);
``--check-rebuild`` runs both in one process and checks that their output files are identical.

Usage: bench/bench_episode.py [WORLD] [--max-sim-time S] [--seed N] [--particles N] [--profile]
       [--rebuild-map | --check-rebuild]
"""
from __future__ import annotations

import argparse
import cProfile
import dataclasses
import functools
import io
import os
import pstats
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from slam_predict.collect import episode, record, stopping  # noqa: E402
from slam_predict.collect.batch import RunSpec  # noqa: E402
from slam_predict.collect.settings import load_settings  # noqa: E402
from slam_predict.explore.explorer import Explorer  # noqa: E402
from slam_predict.nav.layered import LayeredCostmap  # noqa: E402
from slam_predict.nav.local_planner import LocalPlanner  # noqa: E402
from slam_predict.nav.navigator import Navigator  # noqa: E402
from slam_predict.nav.planner import GlobalPlanner  # noqa: E402
from slam_predict.sim import Simulator  # noqa: E402
from slam_predict.slam.gmapping.filter import GMapping  # noqa: E402
from slam_predict.warmup import warm_all  # noqa: E402

# (owner, attribute, component): the methods timed; the component names of the report.
TIMED = (
    (Simulator, "step", "simulator"),
    (GMapping, "update", "GMapping scan processing"),
    (GMapping, "map", "published map (loop)"),
    (LayeredCostmap, "set_map", "costmaps"),
    (LayeredCostmap, "add_scan", "costmaps"),
    (LayeredCostmap, "maybe_update", "costmaps"),
    (Navigator, "add_scan", "costmaps"),
    (GlobalPlanner, "make_plan", "global planner"),
    (LocalPlanner, "compute_velocity_commands", "local planner"),
    (Navigator, "step", "navigator (rest)"),
    (Explorer, "step", "explorer + frontiers"),
    (episode.Recorder, "add", "recording (10 Hz)"),
    (stopping.SnapshotMSE, "add", "snapshots + stop rule"),
    (episode, "full_extent_grid", "snapshots + stop rule"),
    (episode, "grid_to_snapshot", "snapshots + stop rule"),
    (record, "write_snapshot", "snapshots + stop rule"),
)


class Timers:
    """Exclusive wall time per component: nested timed calls are charged to the inner one."""

    def __init__(self):
        self.totals = {}
        self.stack = []  # [component, start, child time]
        self.in_snapshot = False

    def wrap(self, function, component):
        @functools.wraps(function)
        def timed(*args, **kwargs):
            name = component
            if name == "published map (loop)" and self.in_snapshot:
                name = "published map (snapshots)"
            self.stack.append([name, time.perf_counter(), 0.0])
            try:
                return function(*args, **kwargs)
            finally:
                name, start, child = self.stack.pop()
                spent = time.perf_counter() - start
                self.totals[name] = self.totals.get(name, 0.0) + spent - child
                if self.stack:
                    self.stack[-1][2] += spent
        return timed

    def install(self):
        for owner, attribute, component in TIMED:
            setattr(owner, attribute, self.wrap(getattr(owner, attribute), component))
        # the snapshot's map() call happens inside explore_until_stop when a snapshot is due
        original_due = stopping.SnapshotMSE.due

        def due(rule, t):
            self.in_snapshot = original_due(rule, t)
            return self.in_snapshot
        stopping.SnapshotMSE.due = due
        original_stop = episode.stop_reason

        def stop_reason(*args):
            self.in_snapshot = False  # checked right after the snapshot
            return original_stop(*args)
        episode.stop_reason = stop_reason


def bench_settings(args):
    settings = load_settings(args.settings)
    settings.slam.params = dataclasses.replace(settings.slam.params, particles=args.particles)
    if args.max_sim_time is not None:
        settings.stop = dataclasses.replace(settings.stop, max_sim_time_s=args.max_sim_time)
    return settings


def run(args, settings, out_dir):
    world = Path(args.world)
    spec = RunSpec(str(world), world.stem, 0, args.seed, str(out_dir / world.stem / "run_000"))
    return episode.run_episode(spec, settings)


def check_rebuild(args, settings) -> int:
    """Run the episode with the incremental published map, then with the full rebuild, in this
    one process (so both see the same code); print their times and whether every output file
    but run.json (which holds timings) is byte-identical. Exit status 1 if not."""
    files = {}
    with tempfile.TemporaryDirectory() as tmp:
        for incremental in (True, False):
            GMapping.incremental_map = incremental
            cpu0, wall0 = time.process_time(), time.perf_counter()
            result = run(args, settings, Path(tmp) / str(incremental))
            cpu, wall = time.process_time() - cpu0, time.perf_counter() - wall0
            folder = Path(tmp) / str(incremental) / Path(args.world).stem / "run_000"
            files[incremental] = {path.relative_to(folder).as_posix(): path.read_bytes()
                                  for path in sorted(folder.rglob("*")) if path.is_file()}
            print(f"{'incremental' if incremental else 'rebuilt':<11} map: sim "
                  f"{result['sim_duration_s']:.1f} s | wall {wall:.1f} s | CPU {cpu:.1f} s | "
                  f"stop {result['stop_reason']} | coverage {result['coverage']:.4f}")
    names = sorted((set(files[True]) | set(files[False])) - {"run.json"})
    differ = [name for name in names if files[True].get(name) != files[False].get(name)]
    print(f"{len(names) - len(differ)} of {len(names)} output files identical"
          + (f"; differ: {', '.join(differ)}" if differ else ""))
    return 1 if differ else 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("world", nargs="?", default=str(ROOT / "worlds" / "office_1500.world"))
    parser.add_argument("--max-sim-time", type=float, help="s (default: the settings' cap)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--particles", type=int, default=40)
    parser.add_argument("--settings", help="collect settings file (default config/collect.yaml)")
    parser.add_argument("--profile", action="store_true", help="cProfile instead of timers")
    parser.add_argument("--top", type=int, default=35, help="functions shown with --profile")
    parser.add_argument("--rebuild-map", action="store_true",
                        help="rebuild the published map from scratch at every update")
    parser.add_argument("--check-rebuild", action="store_true",
                        help="run twice (incremental map, then rebuilt) and compare the outputs")
    args = parser.parse_args()
    GMapping.incremental_map = not args.rebuild_map
    warm_all()
    settings = bench_settings(args)
    if args.check_rebuild:
        return check_rebuild(args, settings)
    timers = Timers()
    profiler = cProfile.Profile() if args.profile else None
    if not args.profile:
        timers.install()
    with tempfile.TemporaryDirectory() as tmp:
        cpu0, wall0 = time.process_time(), time.perf_counter()
        if profiler:
            profiler.enable()
        result = run(args, settings, Path(tmp))
        if profiler:
            profiler.disable()
        cpu, wall = time.process_time() - cpu0, time.perf_counter() - wall0
    sim = result["sim_duration_s"]
    load = os.getloadavg()
    print(f"== {Path(args.world).stem}, seed {args.seed}, {args.particles} particles"
          f"{', map rebuilt at every update' if args.rebuild_map else ''} | "
          f"stop {result['stop_reason']} | coverage {result['coverage']:.3f} | "
          f"trans {result['metric']['trans_mean']:.3f} m")
    print(f"sim {sim:.1f} s | wall {wall:.1f} s | CPU {cpu:.1f} s | sim/wall {sim / wall:.2f} | "
          f"sim/CPU {sim / cpu:.2f} | load average {load[0]:.1f} {load[1]:.1f} {load[2]:.1f}")
    if profiler:
        stream = io.StringIO()
        stats = pstats.Stats(profiler, stream=stream)
        stats.sort_stats("tottime").print_stats(args.top)
        stats.sort_stats("cumulative").print_stats(args.top)
        print(stream.getvalue())
        return 0
    timers.totals["rest (episode, metric, writing)"] = wall - sum(timers.totals.values())
    for name, seconds in sorted(timers.totals.items(), key=lambda kv: -kv[1]):
        print(f"  {name:<32} {seconds:8.2f} s  {100 * seconds / wall:5.1f} %")
    return 0


if __name__ == "__main__":
    sys.exit(main())
