#!/usr/bin/env python3
"""Episode speed: simulated seconds per CPU second of one collection episode process, per
building, for the campaign-speed targets (>= 8 on every fidelity-campaign building, >= 20 under
1,000 m² of free floor).

Each episode runs in its own process (``python -c`` with ``PYTHONPATH=<tree>/src``, so another
code tree, e.g. a ``git worktree`` of an older commit, can be measured the same way) with the
fidelity campaign's settings (config/fidelity/seed_study.yaml of that tree, sensor logs off) up
to ``--max-sim-time`` s of sim time or the stop rule; the CPU time is the process's own
(``resource.getrusage``: user + system), so other load on the machine changes it little. Worlds
that are not shipped are seed-study buildings imported from ../shared/data into
out/thesis_worlds.

Usage: bench/bench_episode_speed.py [--tree DIR] [--worlds NAME ...] [--max-sim-time S]
           [--seed N]
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_WORLDS = ("Borchen4_updated", "office_h", "lab_intel", "Neulengbach1_updated",
                  "FALAELEM1_updated")
SMALL_M2, SMALL_TARGET, LARGE_TARGET = 1000.0, 20.0, 8.0

EPISODE = """
import dataclasses, json, resource, sys
from slam_predict.collect.batch import RunSpec
from slam_predict.collect.episode import run_episode
from slam_predict.collect.settings import load_settings
world, name, out, max_sim, seed = sys.argv[1:6]
settings = load_settings("config/fidelity/seed_study.yaml")
settings.sensor_logs = False
if float(max_sim) > 0:
    settings.stop = dataclasses.replace(settings.stop, max_sim_time_s=float(max_sim))
record = run_episode(RunSpec(world, name, 0, int(seed), out), settings)
usage = resource.getrusage(resource.RUSAGE_SELF)
print(json.dumps({"sim_s": record["sim_duration_s"], "cpu_s": usage.ru_utime + usage.ru_stime,
                  "free_area_m2": record["free_area_m2"], "stop": record["stop_reason"],
                  "coverage": record["coverage"], "timing": record.get("timing")}))
"""


def world_file(name: str) -> Path:
    """A shipped world, else the seed-study building imported into out/thesis_worlds."""
    shipped = ROOT / "worlds" / f"{name}.world"
    if shipped.is_file():
        return shipped
    imported = ROOT / "out" / "thesis_worlds" / f"{name}.world"
    if not imported.is_file():
        table = ROOT.parent / "shared" / "data" / "thesis" / "environments.csv"
        subprocess.run([sys.executable, "-m", "slam_predict.cli.main", "worlds", "import-thesis",
                        str(table), "--out", str(imported.parent), "--only", name],
                       cwd=ROOT, check=True, capture_output=True,
                       env=dict(os.environ, PYTHONPATH=str(ROOT / "src")))
    return imported


def run_episode(tree: Path, name: str, max_sim: float, seed: int) -> dict:
    """One episode of world ``name`` with the code of ``tree``, in its own process."""
    env = dict(os.environ, PYTHONPATH=str(tree / "src"),
               NUMBA_CACHE_DIR=str(tree / ".numba_cache"))
    with tempfile.TemporaryDirectory(prefix="speed_") as work:
        proc = subprocess.run(
            [sys.executable, "-c", EPISODE, str(world_file(name)), name,
             str(Path(work) / "run"), str(max_sim), str(seed)],
            cwd=tree, env=env, capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"{name} failed with {tree}:\n{proc.stderr[-2000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tree", default=str(ROOT), help="code tree to run (default: this)")
    parser.add_argument("--worlds", nargs="+", default=list(DEFAULT_WORLDS))
    parser.add_argument("--max-sim-time", type=float, default=0.0,
                        help="s of sim time per episode (0: until the stop rule)")
    parser.add_argument("--seed", type=int, default=12345)
    args = parser.parse_args(argv)
    tree = Path(args.tree).resolve()
    print(f"tree {tree}, seed {args.seed}, max sim time {args.max_sim_time or 'stop rule'}")
    print(f"{'world':28s} {'free m2':>8s} {'sim s':>7s} {'CPU s':>7s} {'sim/CPU':>8s} "
          f"{'target':>6s}  stop")
    failed = 0
    for name in args.worlds:
        got = run_episode(tree, name, args.max_sim_time, args.seed)
        ratio = got["sim_s"] / got["cpu_s"]
        target = SMALL_TARGET if got["free_area_m2"] < SMALL_M2 else LARGE_TARGET
        failed += ratio < target
        print(f"{name:28s} {got['free_area_m2']:8.0f} {got['sim_s']:7.0f} {got['cpu_s']:7.1f} "
              f"{ratio:8.2f} {target:6.0f}  {got['stop']} (coverage {got['coverage']:.3f})")
        timing = got.get("timing") or {}
        if timing:
            print("    wall s: " + ", ".join(f"{k} {v:.1f}" for k, v in timing.items()
                                             if isinstance(v, (int, float))))
    print(f"{len(args.worlds) - failed} of {len(args.worlds)} at their target")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
