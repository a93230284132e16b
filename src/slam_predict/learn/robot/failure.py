"""Probability that an exploration fails: the explorer stops with less than
:data:`FAILURE_COVERAGE` of the floor mapped.

The error models learn only from runs that mapped enough of the floor; whether a run gets
there is part of the answer for a robot (short lasers lose their map in open halls and the
seed study's stopping rule then ends the run). :func:`outcome_runs` reads EVERY run record of
the campaigns (failed ones included), :func:`fit_failure` fits a logistic regression on the
same inputs as the error models (plan features and laser range as their log, fov, odometry,
the laser's blind fraction; standardised, L2 penalty ``C``) and :func:`evaluate_failure`
scores it with whole buildings held out: the Brier score against that of always predicting
the training runs' failure rate, and a reliability table. :class:`FailureModel` is the fitted
model as plain arrays (``failure.json`` of the model folder; predicting needs numpy only).
"""
from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from slam_predict.errors import InputError
from slam_predict.learn.card import DEFAULT_SLAM

FAILURE_COVERAGE = 0.9   # a run that maps less of the free area than this failed
FILE = "failure.json"
DEFAULT_C = 1.0          # inverse L2 penalty of the logistic regression (standardised inputs)
BIN_EDGES = (0.0, 0.05, 0.1, 0.2, 0.4, 0.6, 1.0)   # reliability table bins of predicted p
CONSTANT_SPREAD = 1e-9   # an input whose std is below this × max(1, |mean|) is constant


@dataclass
class OutcomeRun:
    """One run of a campaign, successful or not: building, robot inputs, coverage (share)."""

    world: str
    robot: dict[str, float]
    coverage: float


def outcome_runs(folders: Sequence[os.PathLike | str], max_urange_m: float | None,
                 slam: str = DEFAULT_SLAM) -> list[OutcomeRun]:
    """Every run record of SLAM algorithm ``slam`` in the campaign folders (range capped at
    ``max_urange_m``, m)."""
    from slam_predict.learn.robot.inputs import inputs_from_sensor
    from slam_predict.learn.robot.records import slam_records

    out = []
    for path, record in slam_records(folders, slam):
        coverage = record.get("coverage")
        if isinstance(coverage, bool) or not isinstance(coverage, (int, float)) \
                or not math.isfinite(coverage):
            raise InputError(f"'coverage' must be a finite number, got {coverage!r}", path)
        out.append(OutcomeRun(str(record["world"]),
                              inputs_from_sensor(record["sensor"], path, max_urange_m),
                              float(coverage)))
    return out


def outcome_table(runs: Sequence[OutcomeRun], data, names: Sequence[str],
                  threshold: float = FAILURE_COVERAGE
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(X (n, d) raw inputs ``names``, failed (n,) 0/1, building (n,)) of the runs whose
    building has plan features in ``data`` (a :class:`~slam_predict.learn.robot.rundata.
    RunData`)."""
    kept = [r for r in runs if r.world in data.features]
    if not kept:
        raise InputError("no run of a building with plan features: no failure model")
    X = np.array([[data.input_value(r.world, r.robot, n) for n in names] for r in kept])
    failed = np.array([int(r.coverage < threshold) for r in kept])
    return X, failed, np.array([r.world for r in kept])


@dataclass
class FailureModel:
    """A fitted logistic regression as arrays: p = 1 / (1 + exp(−(z · coef + intercept))),
    z = (x' − mean) / scale, x' the inputs with the ``log_columns`` as their log."""

    names: list[str]
    log_columns: list[int]
    mean: np.ndarray
    scale: np.ndarray
    coef: np.ndarray
    intercept: float
    threshold: float = FAILURE_COVERAGE

    def transform(self, X: np.ndarray) -> np.ndarray:
        Z = np.array(np.atleast_2d(X), dtype=float)
        cols = self.log_columns
        Z[:, cols] = np.log(np.maximum(Z[:, cols], 1e-6))
        return (Z - self.mean) / self.scale

    def probability(self, X: np.ndarray) -> np.ndarray:
        """(n,) probability that an exploration with inputs ``X`` (raw, columns ``names``)
        maps less than ``threshold`` of the floor."""
        logit = self.transform(X) @ self.coef + self.intercept
        return 1.0 / (1.0 + np.exp(-np.clip(logit, -50.0, 50.0)))

    def to_form(self) -> dict[str, Any]:
        return {"names": list(self.names), "log_columns": list(self.log_columns),
                "mean": self.mean.tolist(), "scale": self.scale.tolist(),
                "coef": self.coef.tolist(), "intercept": self.intercept,
                "threshold": self.threshold}

    @classmethod
    def from_form(cls, form: Mapping[str, Any]) -> FailureModel:
        return cls([str(n) for n in form["names"]], [int(c) for c in form["log_columns"]],
                   np.asarray(form["mean"], float), np.asarray(form["scale"], float),
                   np.asarray(form["coef"], float), float(form["intercept"]),
                   float(form["threshold"]))


def fit_failure(X: np.ndarray, failed: np.ndarray, names: Sequence[str],
                log_columns: Sequence[int], C: float = DEFAULT_C, seed: int = 0,
                threshold: float = FAILURE_COVERAGE) -> FailureModel:
    """The logistic regression of ``failed`` on ``X`` (module doc); with one class only, a
    constant model at that class's rate (clipped to [0.001, 0.999])."""
    from sklearn.linear_model import LogisticRegression

    cols = [int(c) for c in log_columns]
    Z = np.array(X, dtype=float)
    Z[:, cols] = np.log(np.maximum(Z[:, cols], 1e-6))
    mean, scale = Z.mean(axis=0), Z.std(axis=0)
    # a constant input (one robot's fov in every run) has a spread of rounding noise only
    scale = np.where(scale > CONSTANT_SPREAD * np.maximum(1.0, np.abs(mean)), scale, 1.0)
    if len(np.unique(failed)) < 2:
        rate = float(np.clip(np.mean(failed), 1e-3, 1 - 1e-3))
        return FailureModel(list(names), cols, mean, scale, np.zeros(len(names)),
                            math.log(rate / (1 - rate)), threshold)
    fitted = LogisticRegression(C=C, max_iter=1000, random_state=seed).fit(
        (Z - mean) / scale, failed)
    return FailureModel(list(names), cols, mean, scale, fitted.coef_[0].copy(),
                        float(fitted.intercept_[0]), threshold)


def brier(p: np.ndarray, outcome: np.ndarray) -> float:
    """Mean squared difference between predicted probabilities and 0/1 outcomes."""
    return float(np.mean((np.asarray(p, float) - np.asarray(outcome, float)) ** 2))


def reliability(p: np.ndarray, outcome: np.ndarray,
                edges: Sequence[float] = BIN_EDGES) -> list[dict[str, float]]:
    """Per bin of predicted probability [low, high): runs, mean predicted p, observed failure
    frequency (the last bin includes 1)."""
    rows = []
    for i, (low, high) in enumerate(zip(edges[:-1], edges[1:], strict=True)):
        last = i == len(edges) - 2
        inside = (p >= low) & ((p <= high) if last else (p < high))
        n = int(inside.sum())
        rows.append({"low": float(low), "high": float(high), "runs": n,
                     "predicted": float(p[inside].mean()) if n else math.nan,
                     "observed": float(outcome[inside].mean()) if n else math.nan})
    return rows


def evaluate_failure(X: np.ndarray, failed: np.ndarray, groups: np.ndarray,
                     names: Sequence[str], log_columns: Sequence[int], C: float = DEFAULT_C,
                     seed: int = 0) -> dict[str, Any]:
    """Leave one building out: every run's p from a model fitted without its building; the
    Brier score, that of the training runs' failure rate (per held-out building) and the
    reliability table."""
    p = np.empty(len(failed))
    base = np.empty(len(failed))
    for world in np.unique(groups):
        held = groups == world
        model = fit_failure(X[~held], failed[~held], names, log_columns, C, seed)
        p[held] = model.probability(X[held])
        base[held] = failed[~held].mean()
    return {"protocol": "leave one building out", "runs": int(len(failed)),
            "failed": int(failed.sum()), "buildings": int(len(np.unique(groups))),
            "brier": brier(p, failed), "brier_base_rate": brier(base, failed),
            "reliability": reliability(p, failed)}
