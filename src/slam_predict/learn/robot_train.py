"""Fit the robot-aware models on every run and write the model folder (``models/own-robots``).

Folder (learn/store.py conventions, read back by :class:`~slam_predict.learn.robot_predict.
RobotModel`): ``card.json`` (``"kind": "robots"``), ``<component>.joblib`` =
``{model kind: fitted ComponentModel}`` for every evaluated kind, and ``training_points.csv``
(the POINT rows the models were trained on: partial dependence and the design's coverage).
The card holds the plan feature names and configuration, the robot inputs and units, the
training range of every input, the design (configurations with their robot inputs,
buildings, run counts, angular resolutions), the evaluation figures of every model under
every protocol, the best model per component, the library versions and the SHA-256 of every
file (checked on loading).
"""
from __future__ import annotations

import datetime
import json
import logging
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from slam_predict.atomic import atomic_dir
from slam_predict.config import to_dict
from slam_predict.errors import InputError
from slam_predict.learn.dataset import COMPONENTS, UNITS
from slam_predict.learn.robot_config import RobotLearningConfig
from slam_predict.learn.robot_dataset import RobotDataset, RobotTables, points_csv
from slam_predict.learn.robot_inputs import DESIGN_RESOLUTION_DEG, ROBOT_INPUTS, ROBOT_UNITS
from slam_predict.learn.robot_models import fit_component
from slam_predict.learn.store import CARD, FORMAT, library_versions, sha256

LOG = logging.getLogger(__name__)
KIND = "robots"
POINTS_FILE = "training_points.csv"


def input_ranges(tables: RobotTables) -> dict[str, list[float]]:
    """Input name → [min, max] over the training POINT rows (plan features and robot)."""
    return {name: [float(tables.point_X[:, j].min()), float(tables.point_X[:, j].max())]
            for j, name in enumerate(tables.names)}


def design_summary(data: RobotDataset) -> dict[str, Any]:
    """The design as trained on: configurations, buildings, counts, resolutions."""
    runs = np.array([p.runs for p in data.points])
    return {"configs": data.configs, "buildings": data.worlds, "points": len(data.points),
            "runs": len(data.runs),
            "runs_per_point": {"min": int(runs.min()), "median": float(np.median(runs)),
                               "max": int(runs.max())},
            "angular_resolution_deg": data.resolutions_deg,
            "design_resolution_deg": DESIGN_RESOLUTION_DEG}


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


def build_card(data: RobotDataset, tables: RobotTables, config: RobotLearningConfig,
               summary: Sequence[dict], best: Mapping[str, str], fitted: Mapping[str, dict],
               meta: Mapping[str, Any]) -> dict[str, Any]:
    """The card of a robot-aware model folder (without files and versions)."""
    plan = [n for n in tables.names if n not in ROBOT_INPUTS]
    hashes = data.config_hashes()
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
        "name": meta["name"], "kind": KIND, "description": meta.get("description", ""),
        "created": datetime.date.today().isoformat(), "priority": 0, "setting": KIND,
        "slam_config_hash": ",".join(hashes.get("gmapping", [])), "config_hashes": hashes,
        "feature_version": data.feature_version,
        "feature_config": dict(meta.get("feature_config") or {}), "features": plan,
        "robot_inputs": list(ROBOT_INPUTS), "robot_units": dict(ROBOT_UNITS),
        "input_ranges": input_ranges(tables), "design": design_summary(data),
        "training_buildings": data.worlds, "skipped_runs": dict(data.skipped),
        "confidence": config.confidence,
        "interval_runs": int(round(design_summary(data)["runs_per_point"]["median"])),
        "sources": dict(meta.get("sources") or {}),
        "robot_learning_config": to_dict(config), "components": components}


def save_robot_store(path: os.PathLike | str, card: dict[str, Any],
                     fitted: Mapping[str, Mapping[str, Any]], points_text: str) -> Path:
    """Write the folder atomically: joblib files, the training points, then the card."""
    import joblib

    path = Path(path)
    card = dict(card, format=FORMAT, versions=library_versions(), files={})
    with atomic_dir(path) as tmp:
        os.chmod(tmp, 0o755)
        for component, models in fitted.items():
            name = f"{component}.joblib"
            joblib.dump(dict(models), tmp / name, compress=3)
            card["files"][name] = sha256(tmp / name)
        (tmp / POINTS_FILE).write_text(points_text, encoding="utf-8")
        card["files"][POINTS_FILE] = sha256(tmp / POINTS_FILE)
        (tmp / CARD).write_text(json.dumps(card, indent=2) + "\n", encoding="utf-8")
    LOG.info("robot model %s written to %s", card["name"], path)
    return path


def train_robot_store(data: RobotDataset, config: RobotLearningConfig,
                      summary: Sequence[dict], best: Mapping[str, str],
                      out: os.PathLike | str, meta: Mapping[str, Any],
                      n_jobs: int = 1) -> Path:
    """Fit every model kind on all rows and write the folder ``out``.

    ``meta``: ``name`` (required), ``description``, ``feature_config``, ``sources``.
    """
    if not data.feature_version or data.feature_version == "reference-table":
        raise InputError(f"feature version '{data.feature_version}' cannot be shipped: use "
                         "features computed by slam_predict")
    tables = data.tables(config.plan_features)
    fitted = fit_all(tables, config, n_jobs)
    if not fitted:
        raise InputError("no component could be trained: nothing to store")
    card = build_card(data, tables, config, summary, best, fitted, meta)
    plan = [n for n in tables.names if n not in ROBOT_INPUTS]
    return save_robot_store(out, card, fitted, points_csv(data, plan))
