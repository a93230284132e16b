#!/usr/bin/env python3
"""Issue #18's seed-robot check: does the robot-aware model, given the seed study's realistic
robot, agree with what issue #16's fidelity campaign measured with that robot?

For every building of the campaign (runs with coverage ≥ ``--min-coverage``) whose plan is in
``--worlds``: the model's prediction of mean ε_t and ε_r for ``--robot`` against the campaign's
mean over the building's runs. Prints a table and issue #16's bars (collect/fidelity.py: ε_t
Spearman ≥ 0.85, ε_t median ratio in [0.85, 1.2], ε_r median ratio in [0.7, 1.4], no size
trend), with the model in the role of "ours" and the campaign in that of the reference, and
95 % bootstrap intervals over buildings. ``--unseen`` keeps only the buildings the model was
not trained on. The path-length bar does not apply (the model predicts errors only).

Usage: ``bench/bench_seed_robot_agreement.py [--model DIR] [--campaign DIR] [--worlds DIR]
[--robot FILE] [--min-coverage X] [--unseen]``.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from slam_predict.metric.runs import MIN_COVERAGE

ROOT = Path(__file__).resolve().parents[1]


def parse_args(argv=None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--model", default=str(ROOT / "models" / "own-robots"))
    parser.add_argument("--campaign", default=str(ROOT / "data" / "campaigns"
                                                  / "fidelity_seed_study"))
    parser.add_argument("--worlds", default=str(ROOT / "out" / "thesis_worlds"),
                        help="plans of the campaign's buildings (worlds import-thesis)")
    parser.add_argument("--robot", default=str(ROOT / "config" / "robots"
                                               / "seed_realistic_fixed.yaml"))
    parser.add_argument("--min-coverage", type=float, default=MIN_COVERAGE)
    parser.add_argument("--unseen", action="store_true",
                        help="only buildings the model was not trained on")
    return parser.parse_args(argv)


def comparison_rows(args: argparse.Namespace) -> tuple[list[dict], str]:
    """Per building: runs, free area, model prediction (ours) and campaign mean (theirs)."""
    from slam_predict.learn.featurize import find_plan
    from slam_predict.learn.robot.agreement import agreement_rows
    from slam_predict.learn.robot.predict import RobotModel
    from slam_predict.robot_file import load_robot
    from slam_predict.world.load import load_plan

    model = RobotModel.load(args.model)
    model.check_feature_version()

    def plan_of(world: str):
        path = find_plan(Path(args.worlds), world)
        return None if path is None else load_plan(path)
    rows = agreement_rows(model, model.inputs(load_robot(args.robot)), args.campaign, plan_of,
                          args.min_coverage, args.unseen)
    return rows, model.name


def main(argv=None) -> int:
    from slam_predict.collect.fidelity import Comparison, bootstrap_intervals
    from slam_predict.learn.robot.agreement import error_bars

    args = parse_args(argv)
    rows, name = comparison_rows(args)
    if len(rows) < 3:
        print(f"only {len(rows)} buildings with runs and plans: no comparison", file=sys.stderr)
        return 2
    print(f"model {name}, robot {Path(args.robot).name}, campaign {Path(args.campaign).name}"
          f" ({len(rows)} buildings{', unseen only' if args.unseen else ''})\n")
    print("| building | m² | runs | trained on | ε_t model | ε_t campaign | ratio | ε_r model "
          "| ε_r campaign | ratio |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in sorted(rows, key=lambda r: r["free_area_m2"]):
        print(f"| {r['world']} | {r['free_area_m2']:.0f} | {r['runs']} | "
              f"{'yes' if r['trained_on'] else 'no'} | {r['trans_mean_ours']:.3f} | "
              f"{r['trans_mean_theirs']:.3f} | "
              f"{r['trans_mean_ours'] / r['trans_mean_theirs']:.2f} | "
              f"{r['rot_mean_ours']:.4f} | {r['rot_mean_theirs']:.4f} | "
              f"{r['rot_mean_ours'] / r['rot_mean_theirs']:.2f} |")
    comparison = Comparison(name, rows, {})
    bars = error_bars()
    intervals = bootstrap_intervals(comparison, bars)
    print()
    for bar in bars:
        low, high = intervals[bar.label]
        verdict = "pass" if bar.holds(comparison) else "FAIL"
        print(f"- {bar.label}: {bar.value(comparison):.2f} [95 % {low:.2f}, {high:.2f}] "
              f"({verdict})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
