#!/usr/bin/env python3
"""Do the robot-aware models extrapolate in building size? Trained on the campaign's smaller
buildings, tested on its largest ones (all robot configurations), per model kind.

The leave-buildings-out evaluation rarely asks a model for a building larger than all its
training buildings, while users will (the seed study's campaign has buildings of 2,200–6,222 m²,
the robot campaign none above about 2,100 m²). Here the ``--held`` largest buildings (by
``building_area``) are the test set. Printed per kind and mean component: median % error,
median ratio prediction / measured point mean, and the slope of log(ratio) against
log(building area) over the test points (0: no size bias; < 0: the model falls behind as
buildings grow, as trees alone do past their largest training building).

Usage: ``bench/bench_size_extrapolation.py [DATA_DIR ...] [--features CSV | --worlds DIR]
[--held N] [--models KIND ...] [--config YAML]``; default data: the committed robot campaigns,
features from ``--features`` (e.g. an evaluation folder's features.csv) or ``--worlds``.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DATA = [ROOT / "data" / "campaigns" / "robots", ROOT / "data" / "campaigns" / "robots_rep3"]


def parse_args(argv=None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("data", nargs="*", default=[str(d) for d in DATA])
    source = parser.add_mutually_exclusive_group()
    source.add_argument("--features", help="feature table (an evaluation's features.csv)")
    source.add_argument("--worlds", default=str(ROOT / "out" / "thesis_worlds"))
    parser.add_argument("--held", type=int, default=5, help="largest buildings held out")
    parser.add_argument("--models", nargs="+",
                        default=["elasticnet", "gradient_boosting", "trend_boosting",
                                 "gaussian_process"])
    parser.add_argument("--config", default=str(ROOT / "config" / "robot_learning.yaml"))
    parser.add_argument("--jobs", type=int, default=2)
    return parser.parse_args(argv)


def load_tables(args: argparse.Namespace, config):
    from slam_predict.learn.card import DEFAULT_SLAM
    from slam_predict.learn.robot.rundata import learning_data

    data, _, _ = learning_data(args.data, config, DEFAULT_SLAM, features_csv=args.features,
                               worlds_dir=None if args.features else args.worlds,
                               n_jobs=args.jobs)
    return data.config_tables(config)


def size_split(tables, held: int) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """(train points, test points, test buildings): the ``held`` largest buildings tested."""
    area = tables.point_X[:, tables.names.index("building_area")]
    worlds = np.unique(tables.point_world)
    size = {w: area[tables.point_world == w][0] for w in worlds}
    large = sorted(worlds, key=size.get)[-held:]
    test = np.isin(tables.point_world, large)
    return np.flatnonzero(~test), np.flatnonzero(test), large


def scores(pred: np.ndarray, truth: np.ndarray, area: np.ndarray) -> dict[str, float]:
    ratio = pred / truth
    return {"median_error": float(np.median(np.abs(ratio - 1.0))),
            "median_ratio": float(np.median(ratio)),
            "size_slope": float(np.polyfit(np.log(area), np.log(ratio), 1)[0])}


def main(argv=None) -> int:
    from slam_predict.learn.robot.config import load_robot_learning_config
    from slam_predict.learn.robot.models import MEANS, fit_component

    args = parse_args(argv)
    config = load_robot_learning_config(args.config)
    tables = load_tables(args, config)
    train, test, large = size_split(tables, args.held)
    area = tables.point_X[:, tables.names.index("building_area")]
    print(f"train: {len(np.unique(tables.point_world[train]))} buildings up to "
          f"{area[train].max():.0f} m² ({len(train)} points); test: {', '.join(large)} "
          f"({area[test].min():.0f}–{area[test].max():.0f} m², {len(test)} points)\n")
    print("| component | model | median % error | median ratio | slope of log ratio vs "
          "log area |")
    print("|---|---|---|---|---|")
    for component in MEANS:
        truth = tables.point_y[component][test]
        for kind in args.models:
            model = fit_component(tables.subset(train), component, kind, config)
            s = scores(model.predict(tables.point_X[test]), truth, area[test])
            print(f"| {component} | {kind} | {100 * s['median_error']:.1f} % | "
                  f"{s['median_ratio']:.2f} | {s['size_slope']:+.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
