"""Fit the robot-aware models on every run and write the model folder (``models/own-robots``).

Folder (learn/store.py conventions, read back by :class:`~slam_predict.learn.robot.predict.
RobotModel`): ``card.json`` (``"kind": "robots"``), ``<component>.joblib`` =
``{model kind: fitted ComponentModel}`` for every evaluated kind, ``<component>.plain.json`` =
``{model kind: plain form}`` for those that have one (:mod:`~slam_predict.learn.robot.plain`:
predicting without importing scikit-learn; the card marks them ``"plain": true``), and
``training_points.csv`` (the POINT rows the models were trained on: partial dependence and the
design's coverage). The card holds the plan feature names and configuration, the robot inputs
and units, GMapping's maxUrange the range input is capped at (``max_urange_m``, m; None = no
cap), the training range of every input (robot inputs: widened to the design's bounds when the
design file is given), the design (configurations with their robot inputs, buildings, run
counts, angular resolutions, bounds), the evaluation figures of every model under every
protocol, the best model per component, the library versions and the SHA-256 of every file
(checked on loading).
"""
from __future__ import annotations

import dataclasses
import datetime
import json
import logging
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from slam_predict.config import to_dict
from slam_predict.errors import InputError
from slam_predict.learn.card import POINTS_FILE, ROBOT_KIND
from slam_predict.learn.dataset import COMPONENTS, UNITS, to_csv_text
from slam_predict.learn.robot.config import RobotLearningConfig
from slam_predict.learn.robot.failure import FILE as FAILURE_FILE
from slam_predict.learn.robot.inputs import (
    ALL_ROBOT_INPUTS,
    DERIVED_INPUTS,
    DESIGN_RESOLUTION_DEG,
    ROBOT_UNITS,
    reads_sight_lines,
)
from slam_predict.learn.robot.models import fit_component
from slam_predict.learn.robot.monotone_check import passes
from slam_predict.learn.robot.plain import plain_component
from slam_predict.learn.robot.rundata import RobotTables, RunData
from slam_predict.learn.store import save_store

LOG = logging.getLogger(__name__)


def input_ranges(tables: RobotTables,
                 design: Mapping[str, Sequence[float]] | None = None) -> dict[str, list[float]]:
    """Input name → [min, max] over the training POINT rows (plan features and robot), a
    robot input's widened to the design's bounds ``design`` (input → [low, high]) if given."""
    out = {name: [float(tables.point_X[:, j].min()), float(tables.point_X[:, j].max())]
           for j, name in enumerate(tables.names)}
    for name, (low, high) in (design or {}).items():
        if name not in out:    # the design's resolution, for a model that does not learn it
            continue
        out[name] = [min(out[name][0], float(low)), max(out[name][1], float(high))]
    return out


def design_summary(data: RunData,
                   bounds: Mapping[str, Sequence[float]] | None = None) -> dict[str, Any]:
    """The design as trained on: configurations, buildings, counts, resolutions, and the
    design file's bounds in input units (None without the file)."""
    runs = np.array([len(members) for members in data.groups])
    return {"configs": data.configs, "buildings": data.worlds, "points": len(runs),
            "runs": len(data.runs),
            "runs_per_point": {"min": int(runs.min()), "median": float(np.median(runs)),
                               "max": int(runs.max())},
            "angular_resolution_deg": data.resolutions_deg,
            "design_resolution_deg": DESIGN_RESOLUTION_DEG,
            "bounds": {k: list(v) for k, v in bounds.items()} if bounds else None}


def _metrics(summary: Sequence[dict], component: str, kind: str) -> dict[str, dict]:
    keep = ("n_points", "median_pct_error", "r2", "coverage", "width_median",
            "pass_median_pct_error", "pass_r2", "pass_coverage")
    return {r["protocol"]: {k: r[k] for k in keep} for r in summary
            if r["component"] == component and r["model"] == kind}


def fit_all(tables: RobotTables, config: RobotLearningConfig,
            n_jobs: int = 1) -> dict[str, dict[str, Any]]:
    """{component: {kind: fitted ComponentModel}} on every row; a component without enough
    data (a std without points of 2 or more runs) is left out, logged."""
    from joblib import Parallel, delayed

    def one(component: str, kind: str):
        try:
            return component, kind, fit_component(tables, component, kind, config)
        except InputError as exc:
            LOG.warning("%s not trained: %s", component, exc.one_line())
            return component, kind, None

    done = Parallel(n_jobs=n_jobs)(delayed(one)(c, k) for c in COMPONENTS
                                   for k in config.models)
    fitted: dict[str, dict[str, Any]] = {}
    for component, kind, model in done:
        if model is not None:
            fitted.setdefault(component, {})[kind] = model
    return fitted


def build_card(data: RunData, tables: RobotTables, config: RobotLearningConfig,
               summary: Sequence[dict], best: Mapping[str, str], fitted: Mapping[str, dict],
               meta: Mapping[str, Any]) -> dict[str, Any]:
    """The card of a robot-aware model folder (without files and versions); ``meta``:
    ``name``, ``description``, ``feature_config``, ``sources``, ``design_bounds`` (robot
    input → [low, high] of the design file, optional), ``exploration`` (failed explorations
    per configuration, :func:`slam_predict.learn.robot.outcomes.exploration_outcomes`)."""
    plan = [n for n in tables.names if n not in ALL_ROBOT_INPUTS and n not in DERIVED_INPUTS]
    derived = [n for n in tables.names if n in DERIVED_INPUTS]
    robot = [n for n in tables.names if n in ALL_ROBOT_INPUTS]
    hashes = data.config_hashes()
    bounds = meta.get("design_bounds")
    design = design_summary(data, bounds)
    components = {}
    for component in COMPONENTS:
        if component not in fitted:
            continue
        chosen = best.get(component)
        chosen = chosen if chosen in fitted[component] else next(iter(fitted[component]))
        components[component] = {
            "unit": UNITS[component], "best": chosen,
            "models": {kind: {"metrics": _metrics(summary, component, kind)}
                       for kind in fitted[component]}}
    return {
        "name": meta["name"], "kind": ROBOT_KIND, "description": meta.get("description", ""),
        "created": datetime.date.today().isoformat(), "priority": 0, "setting": ROBOT_KIND,
        "slam": data.slam, "slam_config_hash": ",".join(hashes.get(data.slam, [])),
        "config_hashes": hashes,
        "feature_version": data.feature_version,
        "feature_config": dict(meta.get("feature_config") or {}), "features": plan,
        "robot_inputs": robot, "robot_units": {n: ROBOT_UNITS[n] for n in robot},
        "derived_inputs": derived, **_sightline_entries(data, derived, plan),
        "max_urange_m": data.max_urange_m, "odom_model": data.odom_model,
        "input_ranges": input_ranges(tables, bounds), "design": design,
        "training_buildings": data.worlds, "skipped_runs": dict(data.skipped),
        "confidence": config.confidence,
        "interval_runs": int(round(design["runs_per_point"]["median"])),
        "sources": dict(meta.get("sources") or {}), "exploration": meta.get("exploration"),
        "robot_learning_config": to_dict(config), "components": components}


def _sightline_entries(data: RunData, derived: list[str],
                       plan: list[str]) -> dict[str, Any]:
    """The card's sight-line sampling when the model reads sight lines (a derived input or
    the isotropy feature) and, with a derived input, the training buildings' curves (for the
    partial-dependence plots, which move the laser range and so the blind fraction)."""
    from slam_predict.features.sightline import CURVE_RANGES_M, SightlineConfig

    if not reads_sight_lines(derived, plan):
        return {}
    entries: dict[str, Any] = {
        "sightline": dict(SightlineConfig().to_dict(), ranges_m=list(CURVE_RANGES_M))}
    if derived:
        entries["sightline_curves"] = data.sightline_curves()
    return entries


def plain_forms(fitted: Mapping[str, Mapping[str, Any]],
                X_check: np.ndarray) -> dict[str, dict[str, Any]]:
    """{component: {kind: plain form}} of the fitted models that have one (checked against
    them on ``X_check``, the training inputs, and around; others are logged)."""
    out: dict[str, dict[str, Any]] = {}
    for component, models in fitted.items():
        for kind, model in models.items():
            form = plain_component(model, X_check)
            if form is None:
                LOG.warning("%s %s has no plain form: predict will import scikit-learn",
                            component, kind)
                continue
            out.setdefault(component, {})[kind] = form
    return out


def save_robot_store(path: os.PathLike | str, card: dict[str, Any],
                     fitted: Mapping[str, Mapping[str, Any]], points_text: str,
                     plain: Mapping[str, Mapping[str, Any]] | None = None,
                     extra: Mapping[str, str] | None = None) -> Path:
    """Write the folder atomically (:func:`slam_predict.learn.store.save_store`): joblib
    files, plain forms (``plain``: component → kind → form, marked in the card), the training
    points, then the card."""
    card = dict(card, components=json.loads(json.dumps(card["components"])))   # marked below
    plain = {component: dict(forms) for component, forms in (plain or {}).items() if forms}
    for component in fitted:
        forms = plain.get(component, {})
        for kind, entry in card["components"].get(component, {}).get("models", {}).items():
            entry["plain"] = kind in forms
    LOG.info("robot model %s: writing %s", card["name"], path)
    return save_store(path, card, {c: dict(m) for c, m in fitted.items()}, plain,
                      {POINTS_FILE: points_text, **(extra or {})})


MONOTONE_CHECK_TEXT = (
    "value and interval bounds never fall as the robot gets worse (shorter laser, narrower "
    "fov, larger odometry errors) on a grid over the training box and beyond it (laser "
    "0.1 m to maxUrange, fov 10-360 deg, odometry 0 to 3 x the training maximum), at one "
    "point of each training building; the best model is chosen among those that pass")


def monotone_checks(data: RunData, tables: RobotTables, config: RobotLearningConfig,
                    fitted: Mapping[str, Mapping[str, Any]],
                    ranges: Mapping[str, Sequence[float]]) -> dict[str, dict[str, dict]]:
    """{component: {kind: per-robot-input largest relative drop}} of every fitted model
    (:mod:`~slam_predict.learn.robot.monotone_check`)."""
    from slam_predict.learn.robot.monotone_check import check_fitted, robot_axes

    curves = data.sightline_curves() if "laser_blind_fraction" in tables.names else None
    runs = int(round(float(np.median(tables.point_runs))))
    return check_fitted(fitted, tables, curves, robot_axes(ranges, data.max_urange_m, 5),
                        config.confidence, max(runs, 2))


def monotone_best(best: Mapping[str, str], summary: Sequence[dict],
                  config: RobotLearningConfig,
                  checks: Mapping[str, Mapping[str, Mapping[str, float]]]) -> dict[str, str]:
    """``best`` with every kind that fails the monotone check replaced by the best-ranked
    kind that passes (by ``summary``, else the configuration's order); a component whose
    kinds all fail keeps its best, logged."""
    from slam_predict.learn.robot.evaluate import best_models

    failing = {(c, k) for c, kinds in checks.items() for k, d in kinds.items()
               if not passes(d)}
    ranked = best_models(summary, config, failing)
    out = dict(best)
    for component, kinds in checks.items():
        if (component, out.get(component)) not in failing and component in out:
            continue
        passing = [k for k in config.models if k in kinds and (component, k) not in failing]
        choice = ranked.get(component) or (passing[0] if passing else None)
        if choice is None:
            LOG.warning("%s: no model kind passes the monotone check; shipping %s",
                        component, out.get(component))
            continue
        if component in out:
            LOG.info("%s: %s fails the monotone check, %s ships instead", component,
                     out[component], choice)
        out[component] = choice
    return out


def train_robot_store(data: RunData, config: RobotLearningConfig,
                      summary: Sequence[dict], best: Mapping[str, str],
                      out: os.PathLike | str, meta: Mapping[str, Any],
                      n_jobs: int = 1) -> Path:
    """Fit every model kind on all rows and write the folder ``out``.

    ``meta``: ``name`` (required), ``description``, ``feature_config``, ``sources``,
    ``design_bounds`` (see :func:`build_card`), ``outcome_runs`` (every run of the
    campaigns, :func:`slam_predict.learn.robot.failure.outcome_runs`: the failure probability
    is fitted on them and written as ``failure.json``; none without). The best kind of a
    component is ``best``'s unless it fails the monotone check (:func:`monotone_best`).
    """
    if not data.feature_version or data.feature_version == "reference-table":
        raise InputError(f"feature version '{data.feature_version}' cannot be shipped: use "
                         "features computed by slam_predict")
    tables = data.config_tables(config)
    fitted = fit_all(tables, config, n_jobs)
    if not fitted:
        raise InputError("no component could be trained: nothing to store")
    bounds = meta.get("design_bounds")
    checks = monotone_checks(data, tables, config, fitted, input_ranges(tables, bounds))
    best = monotone_best(best, summary, config, checks)
    card = build_card(data, tables, config, summary, best, fitted, meta)
    for component, entry in card["components"].items():
        for kind, model_entry in entry["models"].items():
            drops = checks[component][kind]
            model_entry["monotone"] = {"passed": passes(drops), "worst_drop": drops}
    card["monotone_check"] = MONOTONE_CHECK_TEXT
    extra = {}
    if meta.get("outcome_runs"):
        every = meta.get("outcome_features")
        outcome_data = data if every is None else dataclasses.replace(
            data, features={w: dict(f) for w, f in every.items()})
        failure, card["failure"] = failure_model(outcome_data, tables, config,
                                                 meta["outcome_runs"])
        extra[FAILURE_FILE] = json.dumps(failure.to_form()) + "\n"
    return save_robot_store(out, card, fitted, to_csv_text(data.tables_points(tables)),
                            plain_forms(fitted, tables.point_X), extra)


def failure_model(data: RunData, tables: RobotTables, config: RobotLearningConfig,
                  runs: Sequence) -> tuple[Any, dict[str, Any]]:
    """(the failure probability model fitted on every run of ``runs``, its card entry with
    the leave-one-building-out evaluation) (:mod:`~slam_predict.learn.robot.failure`)."""
    from slam_predict.learn.robot import failure as fl
    from slam_predict.learn.robot.models import log_columns

    X, failed, groups = fl.outcome_table(runs, data, tables.names, config.failure_coverage)
    columns = log_columns(tables.names, X, config)
    model = fl.fit_failure(X, failed, tables.names, columns, config.failure_c, config.seed,
                           config.failure_coverage)
    evaluation = fl.evaluate_failure(X, failed, groups, tables.names, columns,
                                     config.failure_c, config.seed)
    entry = {"file": FAILURE_FILE, "coverage_threshold": config.failure_coverage,
             "model": f"logistic regression (standardised inputs, C {config.failure_c:g})",
             "runs": int(len(failed)), "failed": int(failed.sum()),
             "base_rate": float(failed.mean()), "evaluation": evaluation}
    return model, entry
