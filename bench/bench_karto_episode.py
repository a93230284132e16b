#!/usr/bin/env python3
"""Episode CPU cost of Karto against GMapping: simulated seconds per CPU second of one in-process
exploration episode of the same building with each back-end.

Each episode (:func:`slam_predict.collect.episode.run_episode`; settings config/collect.yaml for
gmapping, config/collect_karto.yaml for karto: the same robot, navigation, explorer and stop
rule, lockstep SLAM, sensor logs off) runs in a fresh child process, stopped after
``--max-sim-time`` simulated seconds; its CPU time is the child's ``time.process_time`` around
the episode (numba cache warm: a 20 s episode of each back-end runs first, unmeasured). Printed
per building and back-end: sim s, CPU s, sim s per CPU s, distance (m), ε_t (trans_mean, m),
the stop reason.

    nice python bench/bench_karto_episode.py                      # office_500 and office_1500
    nice python bench/bench_karto_episode.py --max-sim-time 600 school_300
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
from collections.abc import Sequence
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BUILDINGS = ["office_500", "office_1500"]      # a small and a mid shipped world
SETTINGS = {"gmapping": "config/collect.yaml", "karto": "config/collect_karto.yaml"}

CHILD = """
import dataclasses, json, sys, tempfile, time
from slam_predict.collect.batch import RunSpec
from slam_predict.collect.episode import run_episode
from slam_predict.collect.settings import load_settings
world, name, settings_path, sim_s, seed = sys.argv[1:6]
settings = load_settings(settings_path)
settings.sensor_logs = False
settings.stop = dataclasses.replace(settings.stop, max_sim_time_s=float(sim_s))
with tempfile.TemporaryDirectory() as out:
    cpu0 = time.process_time()
    rec = run_episode(RunSpec(world, name, 0, int(seed), out), settings)
    cpu = time.process_time() - cpu0
print(json.dumps({"sim_s": rec["sim_duration_s"], "cpu_s": cpu, "distance_m": rec["distance_m"],
                  "trans_mean": rec["metric"]["trans_mean"], "stop": rec["stop_reason"]}))
"""


def parse_args(argv: Sequence[str]) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("buildings", nargs="*", default=BUILDINGS, help="shipped world names")
    parser.add_argument("--max-sim-time", type=float, default=900.0, help="sim s per episode")
    parser.add_argument("--seed", type=int, default=12345, help="run seed")
    parser.add_argument("--backends", nargs="+", default=list(SETTINGS), choices=list(SETTINGS))
    return parser.parse_args(argv)


def run_episode(world: str, backend: str, sim_s: float, seed: int) -> dict:
    """One episode of the shipped ``world`` with ``backend`` in a child process."""
    path = ROOT / "worlds" / f"{world}.world"
    proc = subprocess.run([sys.executable, "-c", CHILD, str(path), world, SETTINGS[backend],
                           str(sim_s), str(seed)], cwd=ROOT, capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"{world} / {backend} failed:\n{proc.stderr[-2000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main(argv: Sequence[str]) -> int:
    args = parse_args(argv)
    print(f"{args.max_sim_time:.0f} sim s per episode, seed {args.seed}")
    for backend in args.backends:                       # fills the numba cache, unmeasured
        run_episode(args.buildings[0], backend, 20.0, args.seed)
    print(f"{'building':<14}{'slam':<10}{'sim s':>7}{'CPU s':>8}{'sim/CPU':>9}{'dist m':>8}"
          f"{'trans m':>9}  stop")
    for world in args.buildings:
        for backend in args.backends:
            r = run_episode(world, backend, args.max_sim_time, args.seed)
            print(f"{world:<14}{backend:<10}{r['sim_s']:>7.0f}{r['cpu_s']:>8.1f}"
                  f"{r['sim_s'] / r['cpu_s']:>9.2f}{r['distance_m']:>8.0f}"
                  f"{r['trans_mean']:>9.4f}  {r['stop']}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
