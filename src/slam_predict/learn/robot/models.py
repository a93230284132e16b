"""Robot-aware models: plan features + robot inputs → the four error components (issue #18).

Inputs: the configured plan features and the robot inputs (:mod:`~slam_predict.learn.robot.inputs`);
model side, the plan features that are > 0 on every training building and the laser range
enter as their log (errors scale as powers of size and range), fov and odometry bounds as they
are (a bound of 0 is a valid robot).

Model kinds (all fitted on the LOG of the target):

- ``elasticnet`` — the linear baseline: :class:`~slam_predict.learn.estimators.ElasticNetGridCV`
  (standardised inputs, l1_ratio/alpha by CV);
- ``gradient_boosting`` — scikit-learn GradientBoostingRegressor (with ``monotone``: the
  same boosting of monotone trees, :mod:`~slam_predict.learn.robot.monotone`);
- ``trend_boosting`` — boosted trees, by default monotone in the inputs whose direction is
  known, inside the training range of the ``trend_boosting.trend_inputs`` (default: the
  building area), and beyond it their fitted power law
  (:class:`~slam_predict.learn.robot.trend.TrendTailBoosting`): trees alone stay flat past
  their largest training building;
- ``gaussian_process`` — GaussianProcessRegressor on standardised inputs, kernel
  C · Matern(anisotropic length scales, ν 2.5) + WhiteKernel, normalised target.

Targets:

- means (``trans_mean``, ``rot_mean``): trained on RUN rows, y = log(run error); the point's
  mean over runs is predicted as exp(f(x) + s²_w/2), s²_w the pooled within-point variance of
  the log run errors (the lognormal mean: exp(E[log ε]) alone is the geometric mean, lower);
- stds (``trans_std``, ``rot_std``): trained on POINT rows with ≥ 2 runs, y = log s² − b(ν),
  s² the sample variance over the point's ν + 1 runs and b(ν) = ψ(ν/2) + log(2/ν) the mean of
  log(χ²_ν/ν) — so y is unbiased for log σ² of normal run errors; predicted std exp(ŷ/2).

Intervals: CV+ (Barber et al. 2021, :func:`slam_predict.learn.intervals.cv_plus_interval`) on
the log scale with folds GROUPED BY BUILDING: each fold model is fitted on the other buildings'
rows and calibrated on the held-out buildings' POINT values (a mean's residual is
log(point mean) − prediction); mapped back with exp. A std's interval covers the sample std of
a point measured over ``runs`` runs (default: the design's 2).
"""
from __future__ import annotations

import logging
import math
import warnings
from dataclasses import dataclass, field

import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.pipeline import Pipeline
from sklearn.preprocessing import StandardScaler
from sklearn.utils.validation import check_is_fitted, validate_data

from slam_predict.errors import InputError
from slam_predict.learn.robot.config import RobotLearningConfig
from slam_predict.learn.robot.inputs import ALL_ROBOT_INPUTS
from slam_predict.learn.robot.plain import (  # noqa: F401  (is_std, MEANS, STDS re-exported)
    MEANS,
    STDS,
    LogScaleModel,
    chi2_log_bias,
    is_std,
)
from slam_predict.learn.robot.rundata import RobotTables

LOG = logging.getLogger(__name__)
STD_FLOOR = 1e-3   # a point's std below 1e-3 × its mean is taken as that (log of 0 is -inf)


def mean_of(component: str) -> str:
    """The run metric a component is computed from (``trans_std`` → ``trans_mean``)."""
    return component.replace("_std", "_mean")


class PositiveLog(TransformerMixin, BaseEstimator):
    """Natural log of the ``columns`` (indices) that are > 0 on every training row.

    Values at or below 0 at prediction time are first raised to 1e-3 × the column's
    training minimum (the caller warns about such inputs: they are outside the training range).
    """

    def __init__(self, columns: tuple[int, ...] = ()):
        self.columns = columns

    def fit(self, X, y=None):
        X = validate_data(self, X)
        self.columns_ = np.array([c for c in self.columns if np.min(X[:, c]) > 0], dtype=int)
        self.floor_ = (1e-3 * X[:, self.columns_].min(axis=0) if len(self.columns_)
                       else np.zeros(0))
        return self

    def transform(self, X):
        check_is_fitted(self)
        X = np.array(validate_data(self, X, reset=False), dtype=float)
        if len(self.columns_):
            X[:, self.columns_] = np.log(np.maximum(X[:, self.columns_], self.floor_))
        return X


def log_columns(names: list[str], X: np.ndarray, config: RobotLearningConfig) -> tuple:
    """Indices of the columns the models see as their log: the configured robot inputs and,
    with ``log_plan_features``, every plan feature > 0 on all rows of ``X``."""
    cols = [j for j, n in enumerate(names) if n in config.log_robot_inputs]
    if config.log_plan_features:
        cols += [j for j, n in enumerate(names)
                 if n not in ALL_ROBOT_INPUTS and np.min(X[:, j]) > 0]
    return tuple(sorted(cols))


def make_estimator(kind: str, names: list[str], columns: tuple, config: RobotLearningConfig):
    """The unfitted pipeline of a model kind over the inputs ``names`` (log ``columns`` →
    [scaling →] regressor)."""
    steps: list = [("log", PositiveLog(columns))]
    if kind == "elasticnet":
        steps.append(("model", _elasticnet(config)))
    elif kind in ("gradient_boosting", "trend_boosting"):
        steps.append(("model", _boosting(kind, names, config)))
    elif kind == "gaussian_process":
        steps += [("scale", StandardScaler()), ("model", _gaussian_process(len(names), config))]
    else:
        raise ValueError(f"unknown robot model kind {kind!r}")
    return Pipeline(steps)


def _elasticnet(config: RobotLearningConfig):
    from slam_predict.learn.estimators import ElasticNetGridCV

    c = config.elasticnet
    return ElasticNetGridCV(l1_ratios=c.l1_ratios, alphas=c.alphas, cv=c.cv,
                            scale_target=c.scale_target, random_state=config.seed)


def _boosting(kind: str, names: list[str], config: RobotLearningConfig):
    """Boosted trees (monotone in the configured inputs, if any); ``trend_boosting`` with
    power-law tails on its trend inputs."""
    from slam_predict.learn.robot.config import MONOTONE_DECREASING, MONOTONE_INCREASING
    from slam_predict.learn.robot.monotone import boosted_trees, monotonic_vector

    c = config.trend_boosting if kind == "trend_boosting" else config.gradient_boosting
    # the known directions, for the inputs this model has (e.g. no blind fraction with
    # sightline_input off)
    cst = None if not c.monotone else monotonic_vector(
        names, [n for n in MONOTONE_INCREASING if n in names],
        [n for n in MONOTONE_DECREASING if n in names])
    if kind == "trend_boosting":
        from slam_predict.learn.robot.trend import TrendTailBoosting

        missing = [n for n in c.trend_inputs if n not in names]
        if missing:
            raise InputError(f"trend_boosting.trend_inputs: {', '.join(missing)} not among "
                             f"the model inputs ({', '.join(names)})")
        columns = tuple(names.index(n) for n in c.trend_inputs)
        return TrendTailBoosting(columns, c.n_estimators, c.learning_rate, c.max_depth,
                                 c.subsample, config.seed, c.min_samples_leaf, cst)
    return boosted_trees(cst, c.n_estimators, c.learning_rate, c.max_depth,
                         c.min_samples_leaf, c.subsample, config.seed)


def _gaussian_process(n_features: int, config: RobotLearningConfig):
    from sklearn.gaussian_process import GaussianProcessRegressor
    from sklearn.gaussian_process.kernels import RBF, ConstantKernel, Matern, WhiteKernel

    c = config.gaussian_process
    scales = np.ones(n_features)
    shape = (RBF(scales, c.length_scale_bounds) if math.isinf(c.nu)
             else Matern(scales, c.length_scale_bounds, nu=c.nu))
    kernel = ConstantKernel(1.0, (1e-3, 1e3)) * shape + WhiteKernel(0.1, c.noise_bounds)
    return GaussianProcessRegressor(kernel, normalize_y=True, n_restarts_optimizer=c.n_restarts,
                                    random_state=config.seed)


def group_folds(groups: np.ndarray, n_folds: int, rng: np.random.Generator) -> np.ndarray:
    """Fold index per row, whole groups per fold: the groups in a seeded random order are
    dealt to min(n_folds, number of groups) folds in turn."""
    unique = np.unique(groups)
    k = min(n_folds, len(unique))
    fold_of_group = np.empty(len(unique), dtype=int)
    fold_of_group[rng.permutation(len(unique))] = np.arange(len(unique)) % k
    return fold_of_group[np.searchsorted(unique, groups)]


def _quiet_fit(estimator, X: np.ndarray, y: np.ndarray):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")   # GP optimiser bounds, ElasticNet convergence notes
        return estimator.fit(X, y)


@dataclass
class ComponentData:
    """What one component's model is fitted and calibrated on (log scale)."""

    X: np.ndarray            # training rows (RUN rows for means, POINT rows for stds)
    y: np.ndarray            # log targets of the training rows
    groups: np.ndarray       # building of each training row
    X_cal: np.ndarray        # calibration POINT rows
    y_cal: np.ndarray        # their log-scale truths (means: log point mean; stds: as y)
    groups_cal: np.ndarray
    offset: float = 0.0      # added to the regressor's output (means: s²_w / 2)


def pooled_log_variance(tables: RobotTables, run_target: str) -> float:
    """Pooled within-point variance of the log run errors (0 when no point has 2 runs)."""
    logs = np.log(tables.run_y[run_target])
    n = len(tables.point_X)
    sums = np.bincount(tables.run_point, logs, n)
    counts = np.bincount(tables.run_point, minlength=n)
    means = sums / np.maximum(counts, 1)
    dof = int(np.sum(np.maximum(counts - 1, 0)))
    return float(np.sum((logs - means[tables.run_point]) ** 2) / dof) if dof else 0.0


def std_rows(tables: RobotTables, component: str) -> np.ndarray:
    """POINT rows usable for a std component (2 or more runs)."""
    return np.flatnonzero((tables.point_runs >= 2) & np.isfinite(tables.point_y[component]))


def std_target(tables: RobotTables, component: str, rows: np.ndarray) -> np.ndarray:
    """log s² − b(ν) of the given POINT rows, s floored at STD_FLOOR × the point mean."""
    s = tables.point_y[component][rows]
    floor = STD_FLOOR * tables.point_y[mean_of(component)][rows]
    dof = tables.point_runs[rows] - 1
    return 2.0 * np.log(np.maximum(s, floor)) - chi2_log_bias(dof)


def component_data(tables: RobotTables, component: str) -> ComponentData:
    """The fitting and calibration data of ``component`` on ``tables``."""
    if is_std(component):
        rows = std_rows(tables, component)
        worlds = tables.point_world[rows]
        if len(rows) < 4 or len(np.unique(worlds)) < 2:
            raise InputError(f"{component} needs points with 2 or more runs in 2 or more "
                             f"buildings (have {len(rows)} such points)")
        X, y = tables.point_X[rows], std_target(tables, component, rows)
        return ComponentData(X, y, worlds, X, y, worlds)
    if len(np.unique(tables.point_world)) < 2:
        raise InputError(f"{component} needs runs in 2 or more buildings")
    offset = 0.5 * pooled_log_variance(tables, component)
    return ComponentData(tables.run_X, np.log(tables.run_y[component]), tables.run_world,
                         tables.point_X, np.log(tables.point_y[component]), tables.point_world,
                         offset)


@dataclass
class ComponentModel(LogScaleModel):
    """A fitted model of one component with its building-grouped CV+ calibration
    (predictions and intervals: :class:`~slam_predict.learn.robot.plain.LogScaleModel`).

    Attributes (fitted):
        estimator: the pipeline fitted on every training row.
        fold_estimators: one pipeline per fold, fitted without that fold's buildings.
        calibration_fold: (n_cal,) fold of each calibration POINT row.
        residuals: (n_cal,) |log truth − fold prediction| of the calibration rows.
        offset: log-scale correction added to every prediction (see module doc).
    """

    component: str
    kind: str
    names: list[str]
    estimator: object = None
    fold_estimators: list = field(default_factory=list)
    calibration_fold: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    residuals: np.ndarray = field(default_factory=lambda: np.zeros(0))
    offset: float = 0.0
    log_columns: tuple = ()

    def evaluate(self, regressor, X: np.ndarray) -> np.ndarray:
        """A fitted pipeline's raw output at rows ``X``."""
        return np.asarray(regressor.predict(X))


def fit_component(tables: RobotTables, component: str, kind: str,
                  config: RobotLearningConfig) -> ComponentModel:
    """Fit ``kind`` for ``component`` on ``tables`` with building-grouped CV+ calibration."""
    data = component_data(tables, component)
    columns = log_columns(tables.names, data.X, config)
    model = ComponentModel(component, kind, list(tables.names), offset=data.offset,
                           log_columns=columns)
    rng = np.random.default_rng([config.seed, 7])
    folds = group_folds(np.concatenate([data.groups, data.groups_cal]),
                        config.conformal_folds, rng)
    train_fold, cal_fold = folds[:len(data.groups)], folds[len(data.groups):]
    residuals = np.empty(len(data.y_cal))
    for k in range(int(folds.max()) + 1):
        fitted = _quiet_fit(make_estimator(kind, tables.names, columns, config),
                            data.X[train_fold != k], data.y[train_fold != k])
        held = cal_fold == k
        if held.any():
            pred = np.asarray(fitted.predict(data.X_cal[held])) + data.offset
            residuals[held] = np.abs(data.y_cal[held] - pred)
        model.fold_estimators.append(fitted)
    model.calibration_fold, model.residuals = cal_fold, residuals
    model.estimator = _quiet_fit(make_estimator(kind, tables.names, columns, config),
                                 data.X, data.y)
    return model
