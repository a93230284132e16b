"""Predictions of a robot-aware model for a campaign's runs, each from the robot it recorded.

The runs of a world are grouped by their run.json ``sensor`` (one group per robot); a group's
robot inputs come from that record (:func:`slam_predict.learn.robot.inputs.inputs_from_sensor`,
the range capped at the card's GMapping maxUrange), its plan features from the world file
with the card's feature and sight-line configuration. Measured: the mean over the group's runs
that explored at least the card's ``exploration.min_coverage`` (the runs the model describes)
and, with 2 or more of them, the std over runs; beside it the model's probability that an
exploration fails and the share of the group's runs that did. A run without a recorded sensor
cannot be scored and is a note.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from slam_predict.errors import InputError
from slam_predict.learn.dataset import COMPONENTS
from slam_predict.report import html as H
from slam_predict.report.campaign import Campaign
from slam_predict.report.predictions import (
    FeatureCache,
    Prediction,
    coverage_line,
    plot,
    predictions_table,
)
from slam_predict.report.sections import robot_text


@dataclass
class RobotGroup:
    """The runs of one world with one recorded robot."""

    world: str
    sensor: dict
    coverages: list[float] = field(default_factory=list)
    errors: list[dict[str, float]] = field(default_factory=list)   # explored runs' metric


def group_runs(campaign: Campaign, min_coverage: float) -> tuple[list[RobotGroup], list[str]]:
    """(groups by world and recorded sensor, notes on runs without one)."""
    from slam_predict.sensor import sensor_hash

    groups: dict[tuple[str, str], RobotGroup] = {}
    unscored: list[str] = []
    for run in campaign.runs:
        sensor = run.record.get("sensor")
        if not isinstance(sensor, dict):
            unscored.append(f"{run.world}/{run.run_id}")
            continue
        group = groups.setdefault((run.world, sensor_hash(sensor)),
                                  RobotGroup(run.world, sensor))
        coverage = float(run.record.get("coverage", math.nan))
        group.coverages.append(coverage)
        metric = run.record.get("metric") or {}
        if coverage >= min_coverage and all(
                isinstance(metric.get(k), (int, float)) for k in ("trans_mean", "rot_mean")):
            group.errors.append({k: float(metric[k]) for k in ("trans_mean", "rot_mean")})
    notes = ([f"{len(unscored)} run(s) record no robot (run.json 'sensor'), so a robot-aware "
              f"model cannot be scored on them: {', '.join(unscored[:5])}"
              + (" …" if len(unscored) > 5 else "")] if unscored else [])
    return list(groups.values()), notes


def measured(group: RobotGroup, component: str) -> float:
    """Mean over the explored runs (means) or their std over runs, ddof 1 (stds); NaN when
    there are too few runs."""
    values = np.array([e[component.replace("_std", "_mean")] for e in group.errors])
    if component.endswith("_mean"):
        return float(values.mean()) if len(values) else math.nan
    return float(values.std(ddof=1)) if len(values) >= 2 else math.nan


@dataclass
class RobotPredictions:
    items: list[Prediction] = field(default_factory=list)
    failures: list[list] = field(default_factory=list)     # table rows
    notes: list[str] = field(default_factory=list)


def predict_groups(model, campaign: Campaign, cache: FeatureCache) -> RobotPredictions:
    """Predictions (and failure probabilities) of ``model`` (a RobotModel) per group."""
    from slam_predict.learn.robot.inputs import inputs_from_sensor

    entry = model.failure_entry or {}
    threshold = float(entry.get("coverage_threshold", math.nan))
    min_coverage = float((model.card.get("exploration") or {}).get("min_coverage", 0.5))
    groups, notes = group_runs(campaign, min_coverage)
    out = RobotPredictions(notes=notes)
    for group in groups:
        label = f"{group.world} [{robot_text(group.sensor)}]"
        try:
            features = cache.features(group.world, model.card)
            inputs = inputs_from_sensor(group.sensor, group.world, model.max_urange_m)
            result = model.predict(features, inputs, float(model.card.get("confidence", 0.9)))
            p = model.failure_probability(features, inputs)
        except InputError as exc:
            out.notes.append(f"{group.world}: no prediction ({exc.one_line()})")
            continue
        for component in COMPONENTS:
            raw = result[component]
            if raw["value"] is None:
                continue
            out.items.append(Prediction(label, component, len(group.errors),
                                        measured(group, component), raw["value"], raw["low"],
                                        raw["high"]))
        failed = sum(c < threshold for c in group.coverages) if p is not None else None
        out.failures.append([label, H.num_cell(len(group.coverages), 0),
                             H.num_cell(p, 3) if p is not None else H.MISSING,
                             f"{failed} of {len(group.coverages)}" if failed is not None
                             else H.MISSING])
    return out


def robot_predictions_section(entry, campaign: Campaign, cache: FeatureCache) -> str:
    """Table, coverage count, failure table, figure and notes of a robot-aware model on the
    campaign's runs, each scored with its own recorded robot."""
    if entry.store is None:
        return ""
    result = predict_groups(entry.store, campaign, cache)
    threshold = (entry.store.failure_entry or {}).get("coverage_threshold")
    body = ("<p>Each row: one world with one robot as its runs recorded it (run.json "
            "<code>sensor</code>); the model predicts from that robot. Measured = over the "
            "runs that explored enough for the model to describe them.</p>")
    if result.items:
        body += predictions_table(result.items)
        body += coverage_line([p for p in result.items if math.isfinite(p.measured)],
                              entry.card.get("confidence"))
    if result.failures:
        share = f"{100 * float(threshold):g} %" if threshold is not None else "the threshold"
        body += (f"<p>Failure probability: the model's probability that an exploration maps "
                 f"less than {share} of the floor, beside the runs that did.</p>")
        body += H.table(["world [robot]", "runs", f"P(coverage < {share})",
                         "runs below it"], result.failures)
    png = plot([replace(p, world=p.world.split(" [laser ")[0] + " " + p.world.split(" [laser ")
                        [-1].split(" m,")[0] + " m") for p in result.items],
               f"{entry.name}: predicted vs measured, per recorded robot (laser range)")
    if png:
        body += H.image(png, f"predicted vs measured, model {entry.name}",
                        "Each point is one world × robot; bar = the model's interval; "
                        "dashed line = perfect prediction.")
    body += H.notes(result.notes)
    return H.section(f"Predictions of {entry.name} for this campaign's runs, per robot", body,
                     level=3)
