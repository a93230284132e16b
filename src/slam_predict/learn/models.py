"""Model identifiers → configured estimators.

Identifiers: ``single:<feature>`` (one per feature), ``fregression``, ``elasticnet``,
``random_forest``, ``gradient_boosting``, and ``reference:<column>`` — a single-feature line on a
reference column of the dataset (e.g. the thesis' own Voronoi distance), used only as a
yardstick in evaluations, never shipped.
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from sklearn.ensemble import GradientBoostingRegressor, RandomForestRegressor

from slam_predict.learn.config import LearningConfig
from slam_predict.learn.conformal import ConformalRegressor
from slam_predict.learn.dataset import REF_PREFIX, Dataset
from slam_predict.learn.estimators import ElasticNetGridCV, FRegressionVoting, SingleFeatureLinear

SINGLE = "single:"
REFERENCE = "reference:"


def model_ids(config: LearningConfig, data: Dataset, with_reference: bool = True) -> list[str]:
    """Every model identifier the configuration asks for on ``data``."""
    ids: list[str] = []
    for kind in config.models:
        if kind == "single":
            ids += [SINGLE + name for name in data.feature_names]
        else:
            ids.append(kind)
    if with_reference:
        ids += [REFERENCE + name[len(REF_PREFIX):] for name in sorted(data.reference)]
    return ids


def is_reference(model_id: str) -> bool:
    """True for yardstick models on reference columns."""
    return model_id.startswith(REFERENCE)


@dataclass
class Design:
    """An unfitted estimator and the matrix it is trained on."""

    estimator: object
    X: np.ndarray
    feature_names: list[str]


def design(model_id: str, data: Dataset, config: LearningConfig) -> Design:
    """The estimator of ``model_id`` and its input matrix on ``data``."""
    seed = config.seed
    if model_id.startswith(REFERENCE):
        column = REF_PREFIX + model_id[len(REFERENCE):]
        return Design(SingleFeatureLinear(0), data.reference[column][:, None], [column])
    names = list(data.feature_names)
    if model_id.startswith(SINGLE):
        feature = model_id[len(SINGLE):]
        return Design(SingleFeatureLinear(names.index(feature)), data.X, names)
    if model_id == "fregression":
        c = config.fregression
        est = FRegressionVoting(max_k=c.max_k, n_subsets=c.n_subsets,
                                subset_fraction=c.subset_fraction, cv=c.cv, random_state=seed)
    elif model_id == "elasticnet":
        c = config.elasticnet
        est = ElasticNetGridCV(l1_ratios=c.l1_ratios, alphas=c.alphas, cv=c.cv,
                               scale_target=c.scale_target, random_state=seed)
    elif model_id == "random_forest":
        c = config.random_forest
        est = RandomForestRegressor(n_estimators=c.n_estimators,
                                    min_samples_leaf=c.min_samples_leaf,
                                    max_features=c.max_features, random_state=seed)
    elif model_id == "gradient_boosting":
        c = config.gradient_boosting
        est = GradientBoostingRegressor(n_estimators=c.n_estimators,
                                        learning_rate=c.learning_rate, max_depth=c.max_depth,
                                        subsample=c.subsample, random_state=seed)
    else:
        raise ValueError(f"unknown model id {model_id!r}")
    return Design(est, data.X, names)


def conformal(estimator, config: LearningConfig) -> ConformalRegressor:
    """``estimator`` wrapped for prediction intervals as the configuration says."""
    c = config.conformal
    return ConformalRegressor(estimator, confidence=c.confidence, method=c.method, cv=c.cv,
                              calibration_fraction=c.calibration_fraction,
                              conformity=c.conformity, random_state=config.seed)


def _unwrap(estimator):
    """The point model inside a ConformalRegressor (the estimator itself otherwise)."""
    return estimator.estimator_ if isinstance(estimator, ConformalRegressor) else estimator


def used_features(estimator, feature_names: Sequence[str]) -> list[str]:
    """Names of the features a fitted estimator relies on (all, for tree ensembles)."""
    inner = _unwrap(estimator)
    support = getattr(inner, "support_", None)
    if support is None:
        return list(feature_names)
    return [feature_names[i] for i in np.asarray(support, dtype=int)]


def describe(estimator) -> dict:
    """Hyperparameters a fitted estimator chose (for tables and cards)."""
    inner = _unwrap(estimator)
    info: dict = {}
    if isinstance(inner, FRegressionVoting):
        info["k"] = inner.k_
    if isinstance(inner, ElasticNetGridCV):
        info.update(alpha=inner.alpha_, l1_ratio=inner.l1_ratio_)
    support = getattr(inner, "support_", None)
    info["n_features"] = (int(len(support)) if support is not None
                          else int(getattr(inner, "n_features_in_", 0)))
    return info
