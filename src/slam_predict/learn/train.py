"""Fit the shipped models on every building and write a model folder with its card.

Per component the store keeps the best model of the evaluation (highest mean test R²) and the
best single-feature line, each wrapped in a :class:`ConformalRegressor` fitted on all buildings.
Linear models and tree ensembles are also written as plain arrays (``<component>.plain.json``,
:mod:`slam_predict.learn.plain`), which ``predict`` evaluates without importing scikit-learn.
"""
from __future__ import annotations

import datetime
import logging
import os
from pathlib import Path
from typing import Any

import numpy as np

from slam_predict.config import to_dict
from slam_predict.errors import InputError
from slam_predict.learn.config import LearningConfig
from slam_predict.learn.dataset import COMPONENTS, UNITS, Dataset
from slam_predict.learn.models import conformal, describe, design, used_features
from slam_predict.learn.plain import plain_form
from slam_predict.learn.results import Outcome
from slam_predict.learn.store import save_store

LOG = logging.getLogger(__name__)
FORBIDDEN_VERSIONS = ("reference-table",)


def check_trainable(data: Dataset) -> None:
    """Refuse datasets that must not become shipped models."""
    version = data.unique("feature_version")
    if version in FORBIDDEN_VERSIONS or version == "":
        raise InputError(f"dataset feature version '{version}' cannot be shipped: models must "
                         "use features computed by slam_predict (slam-predict learn dataset "
                         "--worlds DIR)")
    data.unique("setting")
    data.unique("slam")
    bad = [n for j, n in enumerate(data.feature_names) if not np.isfinite(data.X[:, j]).all()]
    if bad:
        raise InputError(f"feature '{bad[0]}' has missing values; drop it or recompute features")


def _metrics(outcome: Outcome, component: str, model_id: str) -> dict[str, Any]:
    row = next((r for r in outcome.summary
                if r["model"] == model_id and r["component"] == component), None)
    out: dict[str, Any] = {}
    if row is not None:
        out.update({k: row[k] for k in ("r2_mean", "r2_std", "r2_median", "rmse_mean",
                                        "nrmse_mean", "nrmse_all_mean", "pct_error_mean",
                                        "n_splits")})
    loo = next((r for r in outcome.coverage
                if r["model"] == model_id and r["component"] == component), None)
    if loo is not None:
        out["leave_one_out"] = {k: loo[k] for k in ("coverage", "width_mean", "r2", "rmse",
                                                    "pct_error_mean", "pct_error_median")}
    return out


def fit_component(data: Dataset, config: LearningConfig, outcome: Outcome,
                  component: str) -> tuple:
    """Fitted conformal models of one component and their card entry."""
    ids: list[str] = []
    for model_id in (outcome.best.get(component), outcome.best_single.get(component)):
        if model_id and model_id not in ids:
            ids.append(model_id)
    y = data.target(component)
    fitted, entries, plain = {}, {}, {}
    for model_id in ids:
        spec = design(model_id, data, config)
        model = conformal(spec.estimator, config).fit(spec.X, y)
        fitted[model_id] = model
        entries[model_id] = {"features_used": used_features(model, spec.feature_names),
                             "chosen": describe(model),
                             "metrics": _metrics(outcome, component, model_id)}
        form = plain_form(model, len(data.feature_names), spec.X)
        entries[model_id]["plain"] = form is not None
        if form is not None:
            plain[model_id] = form
    card = {"unit": UNITS[component], "best": ids[0], "models": entries}
    return fitted, plain, card


def train_store(data: Dataset, config: LearningConfig, outcome: Outcome, name: str,
                out_dir: os.PathLike | str, description: str = "", priority: int = 0,
                feature_config: dict[str, Any] | None = None,
                sources: dict[str, str] | None = None) -> Path:
    """Fit and write ``out_dir/name``; returns the folder."""
    check_trainable(data)
    if not outcome.best:
        raise InputError("no model predicts any component better than the training mean "
                         "(every mean test R² ≤ 0): nothing to store")
    estimators, plain, components = {}, {}, {}
    for component in COMPONENTS:
        if component not in outcome.best:
            continue
        estimators[component], plain[component], components[component] = fit_component(
            data, config, outcome, component)
    runs = {w: (None if np.isnan(r) else float(r))
            for w, r in zip(data.worlds, data.runs, strict=False)}
    card = {
        "name": name, "description": description,
        "created": datetime.date.today().isoformat(), "priority": int(priority),
        "setting": data.unique("setting"), "slam": data.unique("slam"),
        "slam_config_hash": data.unique("slam_config_hash"),
        "feature_version": data.unique("feature_version"),
        "feature_config": feature_config or {}, "features": list(data.feature_names),
        "feature_ranges": data.feature_ranges(),
        "training_buildings": list(data.worlds), "runs": runs, "sources": sources or {},
        "confidence": config.conformal.confidence, "learning_config": to_dict(config),
        "components": components,
    }
    return save_store(Path(out_dir) / name, card, estimators, plain)
