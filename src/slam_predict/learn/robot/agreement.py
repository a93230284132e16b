"""The seed-robot check of a robot-aware model (issue #18): its predictions for one robot
against a campaign's measured means per building, in the row format of
:class:`slam_predict.collect.fidelity.Comparison` (the model as "ours", the campaign as
"theirs"), so issue #16's bars and bootstrap intervals apply as they are.

Used by ``bench/bench_seed_robot_agreement.py`` and the shipped-model test.
"""
from __future__ import annotations

import os
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from slam_predict.learn.robot.plain import MEANS
from slam_predict.metric.runs import MIN_COVERAGE


def agreement_rows(model, robot: Mapping[str, float], campaign: os.PathLike | str,
                   plan_of: Callable[[str], Any], min_coverage: float = MIN_COVERAGE,
                   unseen: bool = False,
                   features_of: Callable[[Any], Mapping[str, float]] | None = None
                   ) -> list[dict]:
    """One row per building of ``campaign`` with runs of coverage ≥ ``min_coverage`` and a
    plan (``plan_of(world)`` → World, or None to leave the building out): runs, mean free area
    (m²), whether the model was trained on it, and per mean component (``MEANS``) the model's
    prediction for ``robot`` (model inputs, :meth:`RobotModel.inputs`) and the runs' mean
    (m, rad). ``unseen`` leaves out the buildings the model was trained on. ``features_of``
    (plan → its features) defaults to :func:`slam_predict.features.plan.plan_features` with the
    model's feature and sight-line configurations."""
    from slam_predict.collect.record import with_metric
    from slam_predict.collect.store import RunStore
    from slam_predict.features.plan import plan_features

    if features_of is None:
        def features_of(plan):
            return plan_features(plan, model.feature_config, model.sightline_config)

    trained = set(model.card["training_buildings"])
    store = RunStore(Path(campaign))
    rows = []
    for world in store.worlds():
        records = [r for r in with_metric(store.records(world))
                   if float(r["coverage"]) >= min_coverage]
        if not records or (unseen and world in trained):
            continue
        plan = plan_of(world)
        if plan is None:
            continue
        predicted = model.predict(features_of(plan), robot)
        row = {"world": world, "runs": len(records), "trained_on": world in trained,
               "free_area_m2": float(np.mean([r["free_area_m2"] for r in records]))}
        for key in MEANS:
            row[f"{key}_ours"] = float(predicted[key]["value"])
            row[f"{key}_theirs"] = float(np.mean([r["metric"][key] for r in records]))
        rows.append(row)
    return rows


def error_bars():
    """Issue #16's acceptance bars that apply to a model (all but path length)."""
    from slam_predict.collect.fidelity import ACCEPTANCE

    return [bar for bar in ACCEPTANCE if "path_length" not in bar.figure]
