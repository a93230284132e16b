#!/usr/bin/env python3
"""Episode speed per building: simulated seconds per CPU second of one episode process.

Runs one in-process collection episode (:func:`slam_predict.collect.episode.run_episode`, the
fidelity campaign's settings config/fidelity/seed_study.yaml or ``--settings``, sensor logs off)
per building in a fresh child process with the code of a work tree, stopped after
``--max-sim-time`` simulated seconds, and prints the sim time, the child's CPU time (user +
system, numba cache loading included; a 20 s episode first fills the tree's cache, unmeasured)
and their ratio. Buildings: the seed-study worlds (imported from ../shared/data into
out/thesis_worlds once) or shipped worlds. Targets: >= 8 sim s per CPU s on every building of
the campaign, >= 20 below 1,000 m2 of free area (the episode record's ``free_area_m2``); each
row says whether it meets its target. ``still s`` is the longest time the robot stood while the
explorer still ran (the record's ``stuck.longest_still_s``): a row with hundreds of seconds
there timed a robot that stood, not one that explored, and is to be measured again with another
``--seed``.

    python bench/bench_episode_speed.py                              # this tree, five buildings
    python bench/bench_episode_speed.py --all --max-sim-time 1200    # the campaign's 17 buildings
    python bench/bench_episode_speed.py --tree /tmp/e99e84b --max-sim-time 600 lab_intel
"""
from __future__ import annotations

import argparse
import csv
import json
import os
import resource
import subprocess
import sys
from collections.abc import Sequence
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench"))

from bench_no_behaviour_change import world_path  # noqa: E402

# small (333 m2), mid (1,574 m2) and the campaign's three largest (3,089 / 4,988 / 6,222 m2)
BUILDINGS = ["Borchen4_updated", "office_h", "lab_intel", "NLB", "FALAELEM1_updated"]
CAMPAIGN = ROOT / "data" / "campaigns" / "fidelity_seed_study" / "summary.csv"
SMALL_M2 = 1000.0       # free area below which the target is the small buildings' one
TARGET_SMALL = 20.0     # sim s per CPU s, buildings under SMALL_M2
TARGET = 8.0            # sim s per CPU s, every building

CHILD = """
import dataclasses, json, sys, tempfile
from slam_predict.collect.batch import RunSpec
from slam_predict.collect.episode import run_episode
from slam_predict.collect.settings import load_settings
world, name, sim_s, seed = sys.argv[1], sys.argv[2], float(sys.argv[3]), int(sys.argv[4])
settings = load_settings(sys.argv[5])
settings.sensor_logs = False
settings.stop = dataclasses.replace(settings.stop, max_sim_time_s=sim_s)
with tempfile.TemporaryDirectory() as out:
    rec = run_episode(RunSpec(world, name, 0, seed, out), settings)
print(json.dumps({"sim_s": rec["sim_duration_s"], "distance_m": rec["distance_m"],
                  "trans_mean": rec["metric"]["trans_mean"],
                  "still_s": (rec.get("stuck") or {}).get("longest_still_s", 0.0),
                  "free_area_m2": rec["free_area_m2"]}))
"""


def parse_args(argv: Sequence[str]) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("buildings", nargs="*", help="world names (default: five buildings)")
    parser.add_argument("--all", action="store_true",
                        help=f"every building of {CAMPAIGN.relative_to(ROOT)}")
    parser.add_argument("--tree", default=str(ROOT), help="work tree whose code runs")
    parser.add_argument("--max-sim-time", type=float, default=900.0, help="sim s per episode")
    parser.add_argument("--seed", type=int, default=12345, help="run seed")
    parser.add_argument("--settings", default="config/fidelity/seed_study.yaml",
                        help="collection settings, relative to the tree (default: %(default)s)")
    args = parser.parse_args(argv)
    if args.all and args.buildings:
        parser.error("give building names or --all, not both")
    args.buildings = campaign_worlds() if args.all else (args.buildings or BUILDINGS)
    return args


def campaign_worlds() -> list[str]:
    """The worlds of the fidelity campaign's summary.csv, in its order."""
    with CAMPAIGN.open(newline="") as f:
        return [row["world"] for row in csv.DictReader(f)]


def target_for(free_area_m2: float) -> float:
    """The sim s per CPU s a building of ``free_area_m2`` must reach."""
    return TARGET_SMALL if free_area_m2 < SMALL_M2 else TARGET


def child_cpu_s() -> float:
    """CPU time (user + system) of the finished children so far, s."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_building(tree: Path, world: str, sim_s: float, seed: int, settings: str) -> dict:
    """One episode of ``world`` with the code of ``tree`` in a child process; its record
    extract plus ``cpu_s``."""
    env = dict(os.environ, PYTHONPATH=str(tree / "src"),
               NUMBA_CACHE_DIR=str(tree / ".numba_cache"))
    before = child_cpu_s()
    proc = subprocess.run([sys.executable, "-c", CHILD, str(world_path(tree, world)), world,
                           str(sim_s), str(seed), settings], cwd=tree, env=env, capture_output=True,
                          text=True)
    if proc.returncode != 0:
        raise SystemExit(f"{world} failed:\n{proc.stderr[-2000:]}")
    result = json.loads(proc.stdout.strip().splitlines()[-1])
    result["cpu_s"] = child_cpu_s() - before
    return result


def main(argv: Sequence[str]) -> int:
    args = parse_args(argv)
    tree = Path(args.tree).resolve()
    print(f"tree {tree}, {args.settings}, {args.max_sim_time:.0f} sim s, seed {args.seed}")
    run_building(tree, args.buildings[0], 20.0, args.seed, args.settings)   # fills the numba cache
    print(f"{'building':<40}{'free m2':>8}{'sim s':>7}{'CPU s':>8}{'sim/CPU':>9}{'target':>8}"
          f"{'':>6}{'dist m':>8}{'trans':>8}{'still s':>9}")
    failed = 0
    for world in args.buildings:
        r = run_building(tree, world, args.max_sim_time, args.seed, args.settings)
        ratio, target = r["sim_s"] / r["cpu_s"], target_for(r["free_area_m2"])
        verdict = "pass" if ratio >= target else "FAIL"
        failed += verdict == "FAIL"
        print(f"{world:<40}{r['free_area_m2']:>8.0f}{r['sim_s']:>7.0f}{r['cpu_s']:>8.1f}"
              f"{ratio:>9.2f}{'>= ' + format(target, '.0f'):>8}{verdict:>6}"
              f"{r['distance_m']:>8.0f}{r['trans_mean']:>8.4f}{r['still_s']:>9.0f}", flush=True)
    print(f"{len(args.buildings) - failed} of {len(args.buildings)} buildings meet their target")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
