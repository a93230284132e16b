"""Prediction with a robot-aware model folder: plan features + robot inputs → four components.

:class:`RobotModel` loads ``models/<name>`` written by :mod:`train` (card, checksums,
scikit-learn major version checked, as :class:`~slam_predict.learn.store.ModelStore`), then
predicts without refitting anything: per component the best model's value and its CV+
interval. Each best model is read from its plain form (``<component>.plain.json``,
:mod:`~slam_predict.learn.robot.plain`: numpy only) when it has one, else unpickled (which
imports scikit-learn, ≈ 1.5 s). The plan features are computed by the caller with
:attr:`RobotModel.feature_config` and :attr:`RobotModel.sightline_config`
(:func:`slam_predict.features.plan.plan_features`), as for the plan-only models; the robot
inputs with :meth:`RobotModel.inputs` (the laser range capped at the card's GMapping
maxUrange). Load it with :func:`slam_predict.learn.model.load_model`.
"""
from __future__ import annotations

import json
import math
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from slam_predict.errors import InputError, did_you_mean
from slam_predict.learn.card import CARD, POINTS_FILE, ROBOT_KIND, check_kind, input_names
from slam_predict.learn.dataset import COMPONENTS, UNITS
from slam_predict.learn.robot import envelope, resolution
from slam_predict.learn.robot.inputs import (
    ALL_ROBOT_INPUTS,
    DERIVED_INPUTS,
    DERIVED_UNITS,
    ROBOT_UNITS,
    derived_inputs,
    inputs_from_robot,
    reads_sight_lines,
)
from slam_predict.learn.robot.plain import (
    LogScaleModel,
    PlainComponentModel,
    is_std,
)
from slam_predict.learn.store import ModelStore

RANGE_SLACK = 1e-6   # relative: an input this close to a training bound is inside it


class RobotModel:
    """A loaded robot-aware model folder (see the module doc); use :meth:`load`."""

    takes_robot = True

    def __init__(self, store: ModelStore, models: dict[str, LogScaleModel],
                 points: np.ndarray, point_worlds: list[str] | None = None):
        self.store = store
        self.card = store.card
        self.models = models
        self.points = points                       # training POINT inputs (n, d)
        self.point_worlds = list(point_worlds or [])   # their buildings
        self.derived = list(self.card.get("derived_inputs") or [])
        self.names = input_names(self.card)
        self._failure = None

    @classmethod
    def load(cls, path: os.PathLike | str) -> RobotModel:
        """The model folder at ``path``; InputError (one line) on a missing or corrupt folder,
        a checksum mismatch, a folder of another kind or another scikit-learn major version."""
        store = ModelStore(path)   # card, versions and every file's checksum
        check_kind(store.card, ROBOT_KIND, Path(path) / CARD)
        models = {component: _component_model(store, component, entry.get("best"))
                  for component, entry in store.card["components"].items()}
        points, worlds = _read_points(Path(path) / POINTS_FILE, input_names(store.card))
        return cls(store, models, points, worlds)

    @property
    def name(self) -> str:
        return str(self.card["name"])

    @property
    def feature_config(self) -> dict[str, Any]:
        """The feature configuration to compute the plan features with (as predict.py)."""
        return dict(self.card.get("feature_config") or {})

    @property
    def feature_version(self) -> str:
        return str(self.card["feature_version"])

    @property
    def max_urange_m(self) -> float | None:
        """GMapping's maxUrange of the training runs, m (None: no cap): a laser's range
        beyond it is the same robot input."""
        value = self.card["max_urange_m"]
        return None if value is None else float(value)

    def inputs(self, robot) -> dict[str, float]:
        """The card's robot inputs of a :class:`~slam_predict.robot_file.RobotDescription`,
        its laser range capped at :attr:`max_urange_m`."""
        every = inputs_from_robot(robot, self.max_urange_m)
        return {name: every[name] for name in self.names if name in every}

    @property
    def notes(self) -> list[str]:
        """Warnings of the loading (another scikit-learn minor version…)."""
        return self.store.notes

    @property
    def sightline_config(self) -> dict[str, Any] | None:
        """The sight-line sampling (a :class:`~slam_predict.features.sightline.SightlineConfig`
        as a dict) when the model reads the plan's sight-line columns (a derived input or a
        feature of ``sightline.PLAN_COLUMNS``), else None: give it to
        :func:`slam_predict.features.plan.plan_features`."""
        if not reads_sight_lines(self.derived, self.names):
            return None
        stored = dict(self.card.get("sightline") or {})
        stored.pop("ranges_m", None)
        return stored

    def check_feature_version(self) -> None:
        """InputError unless this installation computes the card's feature version."""
        from slam_predict.learn.predict import check_feature_version

        check_feature_version(self.store, retrain="slam-predict learn robots")

    def row(self, plan_features: Mapping[str, float], robot: Mapping[str, float]) -> np.ndarray:
        """The (1, d) raw input row; InputError naming a missing or non-finite input."""
        values = []
        derived: Mapping[str, float] = {}
        if self.derived:
            try:
                derived = derived_inputs(plan_features, robot)
            except KeyError as exc:
                raise InputError(f"model {self.name} needs the plan's sight-line curve and "
                                 f"the laser range (missing {exc.args[0]}): compute the "
                                 "features with model.sightline_config") from None
        for name in self.names:
            source = (robot if name in ALL_ROBOT_INPUTS else derived if name in DERIVED_INPUTS
                      else plan_features)
            if name not in source:
                what = "robot input" if name in ALL_ROBOT_INPUTS else "plan feature"
                raise InputError(f"{what} '{name}' needed by model {self.name} is missing"
                                 + did_you_mean(name, list(source)))
            value = float(source[name])
            if not math.isfinite(value):
                raise InputError(f"input '{name}' must be finite, got {value!r}")
            values.append(value)
        return np.array([values])

    def predict(self, plan_features: Mapping[str, float], robot: Mapping[str, float],
                confidence: float = 0.9, slam: str | None = None) -> dict[str, dict]:
        """{component: {"value", "low", "high", "unit", "model"}} for the four components,
        each monotone in the robot (by construction, or by
        :mod:`~slam_predict.learn.robot.envelope`).

        Means: the point's expected run error and the interval of its mean over the design's
        run count; stds: the run-to-run std σ and the interval of the sample std over that
        many runs (``card["interval_runs"]``, 2 by design). A component the folder has no
        model for gets None values. The value always lies inside its interval. ``slam``:
        None or ``gmapping`` (the training runs' SLAM algorithm). A laser between two trained
        angular resolutions: :mod:`~slam_predict.learn.robot.resolution`.
        """
        from slam_predict.learn.card import check_slam

        check_slam(slam, self.card)
        return resolution.between_resolutions(self, plan_features, robot, confidence)

    def predict_at(self, plan_features: Mapping[str, float], robot: Mapping[str, float],
                   confidence: float) -> dict[str, dict]:
        """:meth:`predict` with the robot's inputs as they are (no resolution blend)."""
        x = self.row(plan_features, robot)
        grid = None
        out: dict[str, dict] = {}
        runs = int(self.card.get("interval_runs", 2))
        for component in COMPONENTS:
            model = self.models.get(component)
            if model is None:
                out[component] = {"value": None, "low": None, "high": None,
                                  "unit": UNITS[component], "model": None}
                continue
            if self.monotone_by_construction(model):
                value, low, high = (float(v[0]) for v in
                                    self._grid_prediction(model, component, x, confidence, runs))
            else:
                grid = grid or self._robot_grid(plan_features, x[0])
                axes, X, shape = grid
                value, low, high = (
                    envelope.interpolate(envelope.envelope(v.reshape(shape)), axes, robot)
                    for v in self._grid_prediction(model, component, X, confidence, runs))
            out[component] = {"value": value, "low": min(low, value), "high": max(high, value),
                              "unit": UNITS[component], "model": f"{self.name}/{model.kind}"}
        return out

    def monotone_by_construction(self, model: LogScaleModel) -> bool:
        """Boosted trees trained with the known directions as monotonic constraints, or a
        linear model (elastic net) that passed the training-time monotone check
        (:mod:`~slam_predict.learn.robot.monotone_check`: signs of a linear model hold
        everywhere); every other model (a Gaussian process, a folder trained before the
        check) is made monotone by :mod:`~slam_predict.learn.robot.envelope`."""
        config = (self.card.get("robot_learning_config") or {}).get(model.kind) or {}
        if model.kind in ("trend_boosting", "gradient_boosting") and config.get("monotone"):
            return True
        entry = self.card["components"].get(model.component, {}).get("models", {})
        check = (entry.get(model.kind) or {}).get("monotone") or {}
        return model.kind == "elasticnet" and check.get("passed") is True

    def _robot_grid(self, plan_features: Mapping[str, float], plan_row: np.ndarray):
        """(axes, input rows, grid shape) of the envelope's robots for one plan (``plan_row``:
        the query's input row, whose robot inputs the grid replaces)."""
        from slam_predict.learn.robot.monotone_check import grid_rows

        axes = envelope.robot_axes(self.card["input_ranges"])
        rows = grid_rows(plan_row, self.names, axes, lambda r: derived_inputs(
            plan_features, {"laser_range_max_m": r})["laser_blind_fraction"])
        return axes, rows.reshape(-1, rows.shape[-1]), rows.shape[:-1]

    @staticmethod
    def _grid_prediction(model, component: str, X: np.ndarray, confidence: float,
                         runs: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(value, low, high) of ``model`` on the rows ``X``, each low ≤ value ≤ high."""
        value = np.asarray(model.predict(X), dtype=float)
        bounds = (model.interval(X, confidence, max(runs, 2)) if is_std(component)
                  else model.interval(X, confidence))
        return value, np.minimum(bounds[:, 0], value), np.maximum(bounds[:, 1], value)

    @property
    def failure_entry(self) -> dict[str, Any] | None:
        """The card's failure-probability entry (threshold, runs, evaluation), None when the
        folder has no failure model (folders trained before it)."""
        entry = self.card.get("failure")
        return dict(entry) if isinstance(entry, Mapping) else None

    def failure_probability(self, plan_features: Mapping[str, float],
                            robot: Mapping[str, float]) -> float | None:
        """Probability that an exploration of the plan with the robot maps less than the
        card's ``failure.coverage_threshold`` of the floor (None without a failure model)."""
        from slam_predict.learn.robot.failure import FailureModel

        entry = self.failure_entry
        if entry is None:
            return None
        if self._failure is None:
            try:
                self._failure = FailureModel.from_form(
                    json.loads(self.store.checked_text(entry["file"])))
            except (KeyError, TypeError, ValueError):
                raise InputError("corrupt model file (failure model)",
                                 self.store.path / str(entry.get("file"))) from None
            if self._failure.names != self.names:
                raise InputError("corrupt model file (failure model inputs differ from the "
                                 "card's)", self.store.path / str(entry["file"]))
        return float(self._failure.probability(self.row(plan_features, robot))[0])

    def resolution_range_deg(self) -> tuple[float, float]:
        """(finest, coarsest) laser angular resolution of the training runs, deg."""
        return resolution.trained_range(self.card)

    def resolution_warning(self, angular_resolution_deg: float) -> str | None:
        """:func:`~slam_predict.learn.robot.resolution.resolution_warning` of this model."""
        return resolution.resolution_warning(self.card, self.names, angular_resolution_deg)

    def domain_warnings(self, plan_features: Mapping[str, float], robot: Mapping[str, float],
                        angular_resolution_deg: float | None = None) -> list[str]:
        """One line per input outside its training range (name, value, range, unit); one for a
        laser angular resolution outside the training runs' range
        (:meth:`resolution_warning`); one when (odom_xy, odom_yaw) lies far from every design
        configuration (see :meth:`odom_gap_warning`); for folders without a failure model,
        the failed explorations near the robot's range (:meth:`exploration_warning`). Each
        line says what to do."""
        x = self.row(plan_features, robot)[0]
        out = []
        units = {**ROBOT_UNITS, **DERIVED_UNITS}
        for name, value in zip(self.names, x, strict=True):
            low, high = self.card["input_ranges"][name]
            slack = RANGE_SLACK * max(1.0, abs(low), abs(high))   # unit conversions' rounding
            if not low - slack <= value <= high + slack:
                unit = f" {units[name]}" if name in units else ""
                out.append(f"{name} = {value:.4g}{unit} is outside the training range "
                           f"[{low:.4g}, {high:.4g}]{unit}: the prediction extrapolates; "
                           "measure this robot on the plan with --simulate 3 to check it")
        if angular_resolution_deg is not None:
            out.append(self.resolution_warning(angular_resolution_deg))
        out.append(self.odom_gap_warning(robot))
        if self.failure_entry is None:   # folders without a failure model: the counts
            out.append(self.exploration_warning(robot))
        return [note for note in out if note]

    def exploration_warning(self, robot: Mapping[str, float]) -> str | None:
        """A line when training runs with a laser range near the robot's failed to explore
        (card ``exploration``, :mod:`~slam_predict.learn.robot.outcomes`), else None."""
        from slam_predict.learn.robot.outcomes import failure_warning

        return failure_warning(self.card.get("exploration"), float(robot["laser_range_max_m"]))

    def odom_model_warning(self, odom_model: str) -> str | None:
        """A warning when the robot's odometry model is not the training runs' (cards
        before the field: ``uniform_per_run``); None when they agree or either is 'none'."""
        trained = str(self.card.get("odom_model", "uniform_per_run"))
        if "none" in (odom_model, trained) or odom_model == trained:
            return None
        return (f"the robot's odometry model is {odom_model}, the model's training runs used "
                f"{trained}: the same error numbers describe a different robot; write "
                f"odom_model: {trained} in the robot file if that reading fits your robot "
                f"(docs/robots.md says which does)")

    def odom_gap_warning(self, robot: Mapping[str, float]) -> str | None:
        """A warning when (odom_xy_error, odom_yaw_error), scaled by the design's spans, lies
        farther from every design configuration than ``joint_factor`` × the design's widest
        nearest-neighbour gap; None otherwise (or with fewer than 2 configurations)."""
        keys = ("odom_xy_error", "odom_yaw_error")
        design = np.array([[c[k] for k in keys]
                           for c in self.card["design"]["configs"].values()])
        if len(design) < 2:
            return None
        span = design.max(axis=0) - design.min(axis=0)
        span = np.where(span > 0, span, 1.0)
        scaled = design / span
        query = np.array([float(robot[k]) for k in keys]) / span
        pair = np.linalg.norm(scaled[:, None] - scaled[None], axis=2)
        np.fill_diagonal(pair, np.inf)
        gap = float(pair.min(axis=1).max())
        factor = float(self.card.get("robot_learning_config", {}).get("joint_factor", 2.0))
        distance = float(np.linalg.norm(scaled - query, axis=1).min())
        if gap > 0 and distance > factor * gap:
            return (f"odometry errors (xy {robot['odom_xy_error']:.4g} m/m, yaw "
                    f"{robot['odom_yaw_error']:.4g} rad/rad) lie far from every design "
                    f"configuration ({distance / gap:.1f} × the design's widest gap): "
                    "measure this robot on the plan with --simulate 3 to check the "
                    "prediction")
        return None

    def partial_dependence(self, component: str, robot_input: str, grid_points: int = 20,
                           span: tuple[float, float] | None = None
                           ) -> tuple[np.ndarray, np.ndarray]:
        """(grid, values): the mean prediction (m or rad) over the training POINT rows with
        ``robot_input`` set to each of ``grid_points`` values spanning its training range
        (or ``span``, (low, high) in the input's unit)."""
        if component not in self.models:
            raise InputError(f"model has no component '{component}'"
                             + did_you_mean(component, list(self.models)))
        robot_inputs = [n for n in self.names if n in ALL_ROBOT_INPUTS]
        if robot_input not in robot_inputs:
            raise InputError(f"unknown robot input '{robot_input}'"
                             + did_you_mean(robot_input, robot_inputs))
        if grid_points < 2:
            raise InputError(f"grid_points must be ≥ 2, got {grid_points}")
        j = self.names.index(robot_input)
        grid = np.linspace(*(span or self.card["input_ranges"][robot_input]), grid_points)
        X = np.repeat(self.points[None], grid_points, axis=0)     # (G, n, d)
        X[:, :, j] = grid[:, None]
        if robot_input == "laser_range_max_m" and "laser_blind_fraction" in self.derived:
            X[:, :, self.names.index("laser_blind_fraction")] = self._blind_grid(grid)
        values = self.models[component].predict(X.reshape(-1, X.shape[2]))
        return grid, values.reshape(grid_points, -1).mean(axis=1)

    def _blind_grid(self, ranges_m: np.ndarray) -> np.ndarray:
        """(G, n) blind fraction of each training point's building at each laser range."""
        from slam_predict.features.sightline import blind_fraction

        curves = self.card.get("sightline_curves") or {}
        missing = sorted(set(self.point_worlds) - set(curves))
        if missing or len(self.point_worlds) != len(self.points):
            raise InputError(f"corrupt model card (no sight-line curve of "
                             f"{missing[0] if missing else 'the training points'})",
                             self.store.path / CARD)
        return np.array([[blind_fraction(curves[w], r) for w in self.point_worlds]
                         for r in ranges_m])


def _component_model(store: ModelStore, component: str, kind: str | None) -> LogScaleModel:
    """The best model of ``component``: its plain form if it has one, else the pickle."""
    if kind is not None:
        form = store.plain(component, kind)
        if form is not None:
            try:
                return PlainComponentModel.from_form(form)
            except (KeyError, TypeError, ValueError):
                raise InputError(f"corrupt model file (plain form of {kind})",
                                 store.path / f"{component}.plain.json") from None
    model = store.estimator(component, kind)
    if not isinstance(model, LogScaleModel):
        raise InputError(f"corrupt model file (no robot model of {component})",
                         store.path / f"{component}.joblib")
    return model


def _read_points(path: Path, names: list[str]) -> tuple[np.ndarray, list[str]]:
    """The (n, d) input columns ``names`` of ``training_points.csv`` (the learning dataset's
    POINT rows, :func:`slam_predict.learn.dataset.read_dataset`) and each row's building."""
    from slam_predict.learn.dataset import read_dataset

    try:
        points = read_dataset(path)
        return points.columns(names), list(points.worlds)
    except InputError as exc:
        raise InputError(f"corrupt training points ({exc.problem})", path) from None
