"""Typed configuration of the robot-aware models (``config/robot_learning.yaml``, section
``robot_learning``; schema: :class:`RobotLearningConfig`)."""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import ClassVar

from slam_predict.config import (
    AT_LEAST_ONE,
    FRACTION,
    NON_NEGATIVE,
    POSITIVE,
    TWO_OR_MORE,
    Range,
)
from slam_predict.learn.card import PROTOCOLS
from slam_predict.learn.config import BoostingConfig, ElasticNetConfig
from slam_predict.metric.runs import MIN_COVERAGE

ROBOT_MODEL_KINDS = ("elasticnet", "gradient_boosting", "trend_boosting", "gaussian_process")
# trend_boosting, not gradient_boosting: the same trees inside the training sizes, and not flat
# past them (bench/bench_size_extrapolation.py)
DEFAULT_MODELS = ("elasticnet", "trend_boosting", "gaussian_process")
# Plan features by default: the building's size (area: the best single feature of the shipped
# plan-only models), the thesis' traversal length (what the odometry error accumulates over),
# the sight lines' isotropy (features/scan_conditioning.py: how evenly the walls a 30 m
# laser sees face every way) and the floor's elongation (features/floor_shape.py: how far
# apart the poses of a relation lie). Few, because a campaign has a few dozen buildings.
DEFAULT_PLAN_FEATURES = ("building_area", "sightline_isotropy", "voronoi_traversal_distance",
                         "floor_elongation")
# Directions known before any data (trend_boosting's monotonic constraints): GMapping's error
# does not fall as the building grows or gets longer and thinner, the laser is blind in more
# directions or the odometry gets worse, and does not rise with a longer or wider laser.
MONOTONE_INCREASING = ("building_area", "floor_elongation", "laser_blind_fraction",
                       "odom_xy_error", "odom_yaw_error")
MONOTONE_DECREASING = ("laser_range_max_m", "laser_fov_deg")


@dataclass
class GaussianProcessConfig:
    """GaussianProcessRegressor: Matern smoothness ``nu`` (0.5, 1.5, 2.5; ``inf`` = RBF),
    anisotropic length scales on standardised inputs + a WhiteKernel; optimiser restarts."""

    nu: float = 2.5
    n_restarts: int = 0
    length_scale_bounds: tuple[float, float] = (0.05, 100.0)
    noise_bounds: tuple[float, float] = (1e-6, 10.0)
    RANGES: ClassVar[dict[str, Range]] = {"nu": POSITIVE, "n_restarts": NON_NEGATIVE,
                                          "length_scale_bounds": POSITIVE,
                                          "noise_bounds": POSITIVE}


@dataclass
class RobotBoostingConfig(BoostingConfig):
    """Boosted regression trees (squared loss on the log target); more, shallower-stepped
    stages than the plan-only models' default: the robot inputs add interactions.

    ``monotone``: the trees respect the directions known before any data
    (:data:`MONOTONE_INCREASING`, :data:`MONOTONE_DECREASING`, for the inputs the model has;
    :mod:`slam_predict.learn.robot.monotone`); without it the trees are scikit-learn's
    GradientBoostingRegressor. ``min_samples_leaf``: rows per leaf at least.
    """

    n_estimators: int = 200
    learning_rate: float = 0.05
    max_depth: int = 3
    min_samples_leaf: int = 1
    monotone: bool = False
    RANGES: ClassVar[dict[str, Range]] = {**BoostingConfig.RANGES,
                                          "min_samples_leaf": AT_LEAST_ONE}


@dataclass
class TrendBoostingConfig(RobotBoostingConfig):
    """``trend_boosting``: the boosting settings, and the inputs whose least-squares trend
    continues past their training range (model side: log of a size or of the range, so the
    trend is a power law).

    Defaults (measured 2026-12-04, docs/notes/learning.md "Monotone trees and repeated evaluation"):
    shallower trees (depth 2, 300 stages, ≥ 5 rows per leaf), monotone in the inputs whose
    direction is known — the error does not fall with the building's area, the laser's blind
    fraction or the odometry error, and does not rise with the laser's range or field of view."""

    n_estimators: int = 300
    max_depth: int = 2
    min_samples_leaf: int = 5
    monotone: bool = True
    trend_inputs: tuple[str, ...] = ("building_area",)


@dataclass
class RobotLearningConfig:
    """Everything ``slam-predict learn robots`` needs (units in the field comments).

    Attributes:
        plan_features: plan features used as inputs (empty = every feature of the table).
        log_plan_features: model-side log of the plan features that are > 0 on every
            training building (sizes and lengths act multiplicatively on the error).
        log_robot_inputs: robot inputs the models see as their log (default the laser range).
        models: model kinds evaluated (and the best per component shipped).
        seed: random_state of folds, trees and the GP optimiser.
        min_coverage: runs whose explored share of the free area is below are skipped.
        folds: GroupKFold folds of each evaluation protocol (``both``: folds² cells).
        repeats: evaluations on as many seeded shufflings of the groups (scores: their mean
            and sd).
        conformal_folds: building-grouped folds of the CV+ intervals.
        confidence: interval coverage (evaluation and the card's default).
        select_protocol: the protocol whose median percentage error picks the best model.
        joint_factor: domain warning when the (odom_xy, odom_yaw) pair lies farther from every
            design configuration than ``joint_factor`` × the design's widest gap.
        max_urange_m: GMapping's maxUrange the runs were collected with, m (the range input is
            min(range_max, maxUrange)); None = read from each run's settings file, checked
            against its recorded GMapping config hash (learn/robot/domain.py).
        sightline_input: also take the plan's blind fraction at the laser's range
            (``laser_blind_fraction``, features/sightline.py) as an input.
        resolution_input: also take the laser's angular resolution (``laser_resolution_deg``,
            deg between beams) as an input: for runs collected at more than one resolution.
        failure_coverage: an exploration that maps less than this share of the free area
            failed (the failure probability's outcome, learn/robot/failure.py).
        failure_c: inverse L2 penalty of the failure probability's logistic regression
            (standardised inputs).
    """

    plan_features: tuple[str, ...] = DEFAULT_PLAN_FEATURES
    log_plan_features: bool = True
    log_robot_inputs: tuple[str, ...] = ("laser_range_max_m",)
    models: tuple[str, ...] = DEFAULT_MODELS
    seed: int = 0
    min_coverage: float = MIN_COVERAGE
    folds: int = 5
    repeats: int = 1
    conformal_folds: int = 5
    confidence: float = 0.9
    select_protocol: str = "both"
    joint_factor: float = 2.0
    max_urange_m: float | None = None
    sightline_input: bool = True
    resolution_input: bool = True
    failure_coverage: float = 0.9
    failure_c: float = 0.3
    elasticnet: ElasticNetConfig = field(default_factory=ElasticNetConfig)
    gradient_boosting: RobotBoostingConfig = field(default_factory=RobotBoostingConfig)
    trend_boosting: TrendBoostingConfig = field(default_factory=TrendBoostingConfig)
    gaussian_process: GaussianProcessConfig = field(default_factory=GaussianProcessConfig)
    RANGES: ClassVar[dict[str, Range]] = {
        "seed": NON_NEGATIVE, "min_coverage": Range(0.0, 1.0), "folds": TWO_OR_MORE,
        "repeats": AT_LEAST_ONE, "conformal_folds": TWO_OR_MORE, "confidence": FRACTION,
        "joint_factor": AT_LEAST_ONE, "max_urange_m": POSITIVE,
        "failure_coverage": FRACTION, "failure_c": POSITIVE}

    @property
    def robot_inputs(self) -> tuple[str, ...]:
        """The robot inputs the models learn (with the resolution when ``resolution_input``)."""
        from slam_predict.learn.robot.inputs import model_robot_inputs

        return model_robot_inputs(self.resolution_input)

    def __post_init__(self) -> None:
        if not self.models:
            raise ValueError("models must name at least one model kind")
        for kind in self.models:
            if kind not in ROBOT_MODEL_KINDS:
                raise ValueError(f"unknown model kind '{kind}' (choose from "
                                 f"{', '.join(ROBOT_MODEL_KINDS)})")
        known = self.robot_inputs
        for name in self.log_robot_inputs:
            if name not in known:
                raise ValueError(f"log_robot_inputs: unknown robot input '{name}' (choose from "
                                 f"{', '.join(known)})")
        if self.select_protocol not in PROTOCOLS:
            raise ValueError(f"select_protocol must be one of {', '.join(PROTOCOLS)}")
        if len(set(self.plan_features)) != len(self.plan_features):
            raise ValueError("plan_features lists a feature twice")


def load_robot_learning_config(path: os.PathLike | str | None) -> RobotLearningConfig:
    """The configuration of ``path`` (section ``robot_learning``, strict), or the defaults."""
    from slam_predict.learn.config import load_section

    if path is None:
        return RobotLearningConfig()
    return load_section(RobotLearningConfig, path, "robot_learning")
