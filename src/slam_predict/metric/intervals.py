"""Confidence intervals over runs: Student t for a mean, chi-square for a standard deviation.

Both assume the per-run values (a run's mean relation error, m or rad) are independent draws
from one normal distribution. They are what ``predict --simulate`` prints beside a model's
prediction:

* mean: x̄ ± t_{1-α/2, n-1} · s/√n with s the unbiased (ddof = 1) sample std;
* std: the point value is the ddof = 0 std, as summary.csv and the models' training targets
  (the seed study's tables use numpy ``std``); its interval is the chi-square interval of the
  population σ, [√((n-1)s²/χ²_{1-α/2, n-1}), √((n-1)s²/χ²_{α/2, n-1})]. A bootstrap interval
  was not used: with the few runs a simulation does (2–60) it is too narrow and, for n < 5,
  degenerate.

Fewer than 2 values give no interval (``low``/``high`` None).
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.stats import chi2, t

from slam_predict.metric.runs import BUILDING_STD_DDOF, SAMPLE_STD_DDOF


@dataclass(frozen=True)
class Estimate:
    """A point value with its interval (None when there are too few values), same unit."""

    value: float
    low: float | None
    high: float | None
    n: int
    confidence: float
    method: str  # "t" or "chi-square"


def _values(values: Sequence[float]) -> np.ndarray:
    array = np.asarray(values, float)
    if array.ndim != 1 or array.size == 0:
        raise ValueError("need a non-empty sequence of values")
    if not np.all(np.isfinite(array)):
        raise ValueError("values must be finite")
    return array


def _check_confidence(confidence: float) -> None:
    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence must be in (0, 1), got {confidence}")


def mean_interval(values: Sequence[float], confidence: float = 0.95) -> Estimate:
    """The mean of ``values`` with its Student-t confidence interval."""
    _check_confidence(confidence)
    x = _values(values)
    n, mean = x.size, float(x.mean())
    if n < 2:
        return Estimate(mean, None, None, n, confidence, "t")
    quantile = float(t.ppf(0.5 + confidence / 2.0, n - 1))
    half = quantile * float(x.std(ddof=SAMPLE_STD_DDOF)) / math.sqrt(n)
    return Estimate(mean, mean - half, mean + half, n, confidence, "t")


def std_interval(values: Sequence[float], confidence: float = 0.95) -> Estimate:
    """The building std (``BUILDING_STD_DDOF``) of ``values`` with the chi-square confidence
    interval of σ."""
    _check_confidence(confidence)
    x = _values(values)
    n, std = x.size, float(x.std(ddof=BUILDING_STD_DDOF))
    if n < 2:
        return Estimate(std, None, None, n, confidence, "chi-square")
    sum_sq = float(np.sum((x - x.mean()) ** 2))  # (n-1)·s²
    alpha = 1.0 - confidence
    low = math.sqrt(sum_sq / float(chi2.ppf(1.0 - alpha / 2.0, n - 1)))
    high = math.sqrt(sum_sq / float(chi2.ppf(alpha / 2.0, n - 1)))
    return Estimate(std, low, high, n, confidence, "chi-square")
