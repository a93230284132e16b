#!/usr/bin/env python3
"""Does a robot's measured error lie inside its predicted 90 % interval? (issue #43)

Runs ``slam-predict predict WORLD --robot ROBOT --simulate RUNS --settings SETTINGS --json``
(fresh runs in a new folder unless ``--out`` names one to resume) and prints, per component,
the measured value over the runs and the robot-aware prediction with its interval. Exit code
0 when the measured mean ε_t and ε_r both lie inside their intervals, 1 otherwise.

The defaults are the issue's check: a UTM-30LX-class laser with twice the realistic odometry
error (config/robots/utm_270_30_poor_odom.yaml, 1,081 beams at 0.25°) on the shipped
school_1000 (1,003 m²), 3 runs, with the settings own-robots' robot campaigns were collected
with (config/robot_campaign/settings.yaml: like with like).

    python bench/bench_robot_simulate_inside.py [--world W] [--robot R] [--runs N]
        [--settings S] [--out DIR] [--jobs K]
"""
from __future__ import annotations

import argparse
import contextlib
import io
import json
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MEANS = ("trans_mean", "rot_mean")


def parse_args(argv=None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--world", default=str(ROOT / "worlds" / "school_1000.world"))
    parser.add_argument("--robot", default=str(ROOT / "config/robots/utm_270_30_poor_odom.yaml"))
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--settings", default=str(ROOT / "config/robot_campaign/settings.yaml"))
    parser.add_argument("--out", default=None, help="simulation folder (default: a new one)")
    parser.add_argument("--jobs", type=int, default=2)
    return parser.parse_args(argv)


def simulate(args: argparse.Namespace) -> dict:
    """The ``predict --simulate --json`` object."""
    from slam_predict.cli.main import main

    out = args.out or tempfile.mkdtemp(prefix="robot_inside_")
    command = ["predict", args.world, "--robot", args.robot, "--simulate", str(args.runs),
               "--settings", args.settings, "--out", str(Path(out) / "sim"), "--jobs",
               str(args.jobs), "--no-progress", "--json"]
    text = io.StringIO()
    with contextlib.redirect_stdout(text):
        code = main(command)
    if code != 0:
        sys.exit(f"slam-predict {' '.join(command)} exited {code}")
    return json.loads(text.getvalue())


def main(argv=None) -> int:
    args = parse_args(argv)
    start = time.monotonic()
    result = simulate(args)
    measured = result["simulation"]["measured"]
    print(f"{result['world']}, robot {args.robot}, {result['simulation']['runs']} runs, "
          f"model {result['model_store']} ({time.monotonic() - start:.0f} s)")
    print("| component | measured | predicted | 90 % interval | inside |")
    print("|---|---|---|---|---|")
    inside = {}
    for component in ("trans_mean", "trans_std", "rot_mean", "rot_std"):
        m, p = measured[component], result[component]
        value = m.get("value") if m.get("status") == "ok" else None
        inside[component] = value is not None and p["low"] <= value <= p["high"]
        shown = "n/a" if value is None else f"{value:.4g}"
        print(f"| {component} | {shown} | {p['value']:.4g} | {p['low']:.4g}–{p['high']:.4g} | "
              f"{'yes' if inside[component] else 'no'} |")
    verdict = all(inside[c] for c in MEANS)
    print(f"- measured mean ε_t and ε_r inside their intervals: {'yes' if verdict else 'NO'}")
    return 0 if verdict else 1


if __name__ == "__main__":
    sys.exit(main())
