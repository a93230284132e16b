#!/usr/bin/env python3
"""What the laser's angular resolution does to the error, measured against a robot-aware model
(issue #43): against one without the resolution input, how far runs at other resolutions lie
from its predictions; against one that learnt them (own-robots since 2026-12-06), in-sample.

For every usable run of the campaigns (the learner's rule, ``records.skip_reason``, with
coverage ≥ ``--min-coverage``): the model's prediction for the run's robot (the model's robot
inputs) on the run's building, and the run's measured mean ε_t and ε_r.
Prints, per angular resolution of the runs, the median ratio measured ÷ predicted and the
share of runs inside the 90 % interval of a point mean — a resolution the model
generalises to has ratios near those of the training resolution.

Usage: ``bench/bench_resolution_effect.py DATA_DIR... [--model DIR] [--worlds DIR]
[--min-coverage X]``.
"""
from __future__ import annotations

import argparse
import sys
from collections import defaultdict
from pathlib import Path

import numpy as np

from slam_predict.metric.runs import MIN_COVERAGE

ROOT = Path(__file__).resolve().parents[1]


def parse_args(argv=None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("data", nargs="+", metavar="DATA_DIR")
    parser.add_argument("--model", default=str(ROOT / "models" / "own-robots"))
    parser.add_argument("--worlds", default=str(ROOT / "out" / "thesis_worlds"))
    parser.add_argument("--min-coverage", type=float, default=MIN_COVERAGE)
    return parser.parse_args(argv)


def run_rows(args: argparse.Namespace) -> list[dict]:
    """Per usable run: resolution (deg), measured and predicted means with the interval."""
    from slam_predict.features.plan import plan_features
    from slam_predict.learn.featurize import find_plan
    from slam_predict.learn.robot.inputs import angular_resolution_deg, inputs_from_sensor
    from slam_predict.learn.robot.predict import RobotModel
    from slam_predict.learn.robot.records import find_records, read_record, skip_reason
    from slam_predict.world.load import load_plan

    model = RobotModel.load(args.model)
    model.check_feature_version()
    features: dict[str, dict] = {}
    rows = []
    for path in find_records(args.data):
        record = read_record(path)
        if skip_reason(record, args.min_coverage, path) is not None:
            continue
        world = record["world"]
        if world not in features:
            plan = find_plan(Path(args.worlds), world)
            features[world] = plan_features(load_plan(plan), model.feature_config,
                                            model.sightline_config)
        robot = inputs_from_sensor(record["sensor"], path, model.max_urange_m)
        predicted = model.predict(features[world], robot)
        row = {"world": world, "resolution": angular_resolution_deg(record["sensor"], path)}
        for key in ("trans_mean", "rot_mean"):
            entry = predicted[key]
            row[key] = (float(record["metric"][key]), entry["value"], entry["low"], entry["high"])
        rows.append(row)
    return rows


def main(argv=None) -> int:
    args = parse_args(argv)
    groups: dict[float, list[dict]] = defaultdict(list)
    for row in run_rows(args):
        groups[round(row["resolution"], 2)].append(row)
    print("| resolution (deg) | runs | ε_t measured ÷ predicted (median) | inside | "
          "ε_r measured ÷ predicted (median) | inside |")
    print("|---|---|---|---|---|---|")
    for resolution, rows in sorted(groups.items()):
        cells = []
        for key in ("trans_mean", "rot_mean"):
            ratios = [m / p for m, p, _, _ in (r[key] for r in rows)]
            inside = np.mean([lo <= m <= hi for m, _, lo, hi in (r[key] for r in rows)])
            cells += [f"{np.median(ratios):.2f}", f"{100 * inside:.0f} %"]
        print(f"| {resolution:g} | {len(rows)} | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
