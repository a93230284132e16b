"""Typed configuration of learning and evaluation (``config/learning.yaml``)."""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Any, ClassVar

from slam_predict.config import (
    AT_LEAST_ONE,
    FRACTION,
    NON_NEGATIVE,
    POSITIVE,
    PROBABILITY,
    TWO_OR_MORE,
    Range,
)
from slam_predict.errors import InputError, did_you_mean
from slam_predict.learn.estimators import THESIS_ALPHAS, THESIS_L1_RATIOS

MODEL_KINDS = ("single", "fregression", "elasticnet", "random_forest", "gradient_boosting")


@dataclass
class FRegressionConfig:
    """F-regression voting: subsets per K, their size, inner CV folds, largest K (None = F)."""

    n_subsets: int = 100
    subset_fraction: float = 0.8
    cv: int = 5
    max_k: int | None = None
    RANGES: ClassVar[dict[str, Range]] = {
        "n_subsets": AT_LEAST_ONE, "subset_fraction": Range(0.0, 1.0, open_low=True),
        "cv": TWO_OR_MORE, "max_k": AT_LEAST_ONE}


@dataclass
class ElasticNetConfig:
    """ElasticNet grids (the thesis') and CV folds; ``scale_target`` standardises y too."""

    l1_ratios: tuple[float, ...] = THESIS_L1_RATIOS
    alphas: tuple[float, ...] = THESIS_ALPHAS
    cv: int = 5
    scale_target: bool = True
    RANGES: ClassVar[dict[str, Range]] = {
        "l1_ratios": PROBABILITY, "alphas": NON_NEGATIVE, "cv": TWO_OR_MORE}


@dataclass
class ForestConfig:
    """scikit-learn RandomForestRegressor settings."""

    n_estimators: int = 100
    min_samples_leaf: int = 2
    max_features: float = 0.5
    RANGES: ClassVar[dict[str, Range]] = {
        "n_estimators": AT_LEAST_ONE, "min_samples_leaf": AT_LEAST_ONE,
        "max_features": Range(0.0, 1.0, open_low=True)}


@dataclass
class BoostingConfig:
    """scikit-learn GradientBoostingRegressor settings."""

    n_estimators: int = 100
    learning_rate: float = 0.1
    max_depth: int = 2
    subsample: float = 0.8
    RANGES: ClassVar[dict[str, Range]] = {
        "n_estimators": AT_LEAST_ONE, "learning_rate": POSITIVE, "max_depth": AT_LEAST_ONE,
        "subsample": Range(0.0, 1.0, open_low=True)}


@dataclass
class ConformalConfig:
    """Prediction intervals: coverage, ``cv_plus`` or ``split``, conformity score."""

    confidence: float = 0.9
    method: str = "cv_plus"
    cv: int = 5
    calibration_fraction: float = 0.25
    conformity: str = "absolute"
    RANGES: ClassVar[dict[str, Range]] = {
        "confidence": FRACTION, "cv": TWO_OR_MORE, "calibration_fraction": FRACTION}


@dataclass
class EvaluationConfig:
    """Repeated random splits (seeds first_seed … first_seed + n_splits − 1) and LOBO."""

    n_splits: int = 20
    first_seed: int = 0
    test_fraction: float = 0.2
    leave_one_out: bool = True
    loo_models: str = "best"  # "best": best + best single per component; "all": every kind
    RANGES: ClassVar[dict[str, Range]] = {
        "n_splits": AT_LEAST_ONE, "first_seed": NON_NEGATIVE, "test_fraction": FRACTION}


@dataclass
class LearningConfig:
    """Everything ``slam-predict learn`` needs; ``seed`` feeds every estimator's random_state."""

    models: tuple[str, ...] = MODEL_KINDS
    seed: int = 0
    fregression: FRegressionConfig = field(default_factory=FRegressionConfig)
    elasticnet: ElasticNetConfig = field(default_factory=ElasticNetConfig)
    random_forest: ForestConfig = field(default_factory=ForestConfig)
    gradient_boosting: BoostingConfig = field(default_factory=BoostingConfig)
    conformal: ConformalConfig = field(default_factory=ConformalConfig)
    evaluation: EvaluationConfig = field(default_factory=EvaluationConfig)
    RANGES: ClassVar[dict[str, Range]] = {"seed": NON_NEGATIVE}

    def __post_init__(self) -> None:
        for kind in self.models:
            if kind not in MODEL_KINDS:
                raise ValueError(f"unknown model kind '{kind}' (choose from "
                                 f"{', '.join(MODEL_KINDS)})")
        if self.conformal.method not in ("cv_plus", "split"):
            raise ValueError("conformal.method must be 'cv_plus' or 'split'")
        if self.conformal.conformity not in ("absolute", "scaled"):
            raise ValueError("conformal.conformity must be 'absolute' or 'scaled'")
        if self.evaluation.loo_models not in ("best", "all"):
            raise ValueError("evaluation.loo_models must be 'best' or 'all'")
        if not 0.0 < self.evaluation.test_fraction < 1.0:
            raise ValueError("evaluation.test_fraction must lie in (0, 1)")


def yaml_section(path: os.PathLike | str, section: str) -> dict[str, Any]:
    """The ``section`` mapping of a YAML config file, strictly.

    A file holding ``section:`` may hold nothing else at the top level (a misspelt or foreign
    key is refused, not ignored); a file without it is taken as the section itself (the
    dataclass loader then refuses unknown keys at every level).
    """
    return _section_and_path(path, section)[0]


def load_section(cls, path: os.PathLike | str, section: str):
    """Dataclass ``cls`` from the ``section`` of a YAML file (see :func:`yaml_section`), with
    error messages naming keys by their full path in the file."""
    from slam_predict.config import from_dict

    data, key_path = _section_and_path(path, section)
    return from_dict(cls, data, str(path), key_path=key_path)


def _section_and_path(path: os.PathLike | str, section: str) -> tuple[dict[str, Any], str]:
    """The section's mapping and its key path in the file ('' when the file is the section)."""
    from slam_predict.config import check_keys, load_yaml

    data = load_yaml(path)
    if section not in data:
        misspelt = [key for key in data if did_you_mean(str(key), [section])]
        if misspelt:   # 'featres:' is the section misspelt, not a flat file
            check_keys({misspelt[0]: None}, [section], str(path))
        return data, ""
    check_keys(data, [section], str(path))
    value = data[section]
    if value is None:
        return {}, section
    if not isinstance(value, dict):
        raise InputError(f"'{section}' must be a mapping", path)
    return value, section
