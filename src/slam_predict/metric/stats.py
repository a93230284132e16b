"""Summary statistics of error samples: mean, std, min, max, N — in one pass or merged by chunks.

``std`` uses ``ddof`` given explicitly: 1 (sample std, n − 1) for the per-relation errors of a
run, as Cartographer's relations metric prints them; 0 for the spread of per-run errors across
runs of a building (thesis eqs. 3.7/3.9, numpy ``std`` in the thesis' data release).
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np


@dataclass(frozen=True)
class ErrorStatistics:
    """Statistics of one error series (units of the series)."""

    mean: float
    std: float
    min: float
    max: float
    n: int
    ddof: int = 1
    rmse: float = math.nan

    def to_dict(self) -> dict:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict) -> ErrorStatistics:
        return cls(**data)

    def scaled(self, factor: float, power: int = 1) -> ErrorStatistics:
        """The statistics of the series multiplied by ``factor**power`` (e.g. rad → deg)."""
        k = float(factor) ** power
        return ErrorStatistics(self.mean * k, self.std * k, self.min * k, self.max * k, self.n,
                               self.ddof, self.rmse * k)


def compute_statistics(values, ddof: int = 1) -> ErrorStatistics:
    """Statistics of ``values`` (1-D). Empty input gives NaNs and n = 0; std is NaN if n ≤ ddof."""
    values = np.asarray(values, dtype=float).reshape(-1)
    n = len(values)
    if n == 0:
        return ErrorStatistics(math.nan, math.nan, math.nan, math.nan, 0, ddof, math.nan)
    std = float(np.std(values, ddof=ddof)) if n > ddof else math.nan
    return ErrorStatistics(float(np.mean(values)), std, float(np.min(values)),
                           float(np.max(values)), n, ddof, float(np.sqrt(np.mean(values ** 2))))


class StreamingStatistics:
    """Mean/std/min/max/RMSE over chunks, merged with Chan et al.'s pairwise update (stable)."""

    def __init__(self, ddof: int = 1):
        self.ddof = ddof
        self.n = 0
        self.mean = 0.0
        self.m2 = 0.0
        self.sum_sq = 0.0
        self.min = math.inf
        self.max = -math.inf

    def update(self, values) -> None:
        """Add a chunk of values."""
        values = np.asarray(values, dtype=float).reshape(-1)
        if len(values) == 0:
            return
        mean_b = float(values.mean())
        self.merge(len(values), mean_b, float(((values - mean_b) ** 2).sum()),
                   float(values.min()), float(values.max()), float((values ** 2).sum()))

    def merge(self, n_b: int, mean_b: float, m2_b: float, min_b: float, max_b: float,
              sum_sq_b: float) -> None:
        """Add a chunk given by its moments (count, mean, sum of squared deviations, ...)."""
        if n_b == 0:
            return
        n = self.n + n_b
        delta = mean_b - self.mean
        self.mean += delta * n_b / n
        self.m2 += m2_b + delta * delta * self.n * n_b / n
        self.n = n
        self.sum_sq += sum_sq_b
        self.min = min(self.min, min_b)
        self.max = max(self.max, max_b)

    def result(self) -> ErrorStatistics:
        if self.n == 0:
            return compute_statistics([], self.ddof)
        std = math.sqrt(self.m2 / (self.n - self.ddof)) if self.n > self.ddof else math.nan
        return ErrorStatistics(self.mean, std, self.min, self.max, self.n, self.ddof,
                               math.sqrt(self.sum_sq / self.n))

