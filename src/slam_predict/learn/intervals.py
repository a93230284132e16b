"""Conformal interval arithmetic on plain arrays (no scikit-learn import).

Shared by :class:`slam_predict.learn.conformal.ConformalRegressor` and by the plain-array
prediction path of :mod:`slam_predict.learn.plain`.
"""
from __future__ import annotations

import math

import numpy as np


def conformal_rank(n: int, alpha: float) -> int:
    """1-based rank ⌈(1 − α)(n + 1)⌉ of the conformal quantile among n scores (> n = infinite)."""
    return int(math.ceil((1.0 - alpha) * (n + 1) - 1e-9))


def upper_quantile(values: np.ndarray, alpha: float, axis: int = -1) -> np.ndarray:
    """The ⌈(1 − α)(n + 1)⌉-th smallest of ``values`` along ``axis`` (+inf when n is too small)."""
    values = np.sort(values, axis=axis)
    n = values.shape[axis]
    rank = conformal_rank(n, alpha)
    if rank > n:
        shape = list(values.shape)
        del shape[axis]
        return np.full(shape, np.inf)
    return np.take(values, rank - 1, axis=axis)


def residual_scale(prediction: np.ndarray, conformity: str, floor: float) -> np.ndarray:
    """Divisor of the residuals: 1 (absolute) or max(|ŷ|, floor) (scaled)."""
    if conformity == "absolute":
        return np.ones_like(prediction)
    return np.maximum(np.abs(prediction), floor)


def split_interval(pred: np.ndarray, quantile: float, conformity: str,
                   floor: float) -> np.ndarray:
    """(n, 2) split-conformal bounds around predictions ``pred``."""
    half = quantile * residual_scale(pred, conformity, floor)
    return np.column_stack([pred - half, pred + half])


def cv_plus_interval(fold_pred: np.ndarray, fold_of: np.ndarray, residuals: np.ndarray,
                     alpha: float, conformity: str, floor: float) -> np.ndarray:
    """(n, 2) CV+ bounds from fold-model predictions ``fold_pred`` (K, n).

    Training row i contributes ŷ_{-k(i)}(x) ± R_i; the bounds are the conformal quantiles of
    those lower and upper values (Barber et al. 2021).
    """
    per_row = fold_pred[fold_of]  # (n_train, n_test)
    half = residuals[:, None] * residual_scale(per_row, conformity, floor)
    high = upper_quantile(per_row + half, alpha, axis=0)
    low = -upper_quantile(-(per_row - half), alpha, axis=0)
    return np.column_stack([low, high])
