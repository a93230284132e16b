"""How sure a fidelity figure is: bootstrap intervals of issue #16's bars.

A campaign holds a few runs per building and a few dozen buildings, so a bar's figure (a
Spearman correlation, a median ratio, the size trend) moves with the runs that happened to be
drawn and the buildings that happened to be chosen. Each bootstrap draw resamples the buildings
with replacement and, within each drawn building, its runs with replacement, recomputes our
per-building means (the seed study's stay fixed: they average ≥ 10 runs each) and then the
figure. The interval is the draws' central quantiles. A building with one run contributes no
within-building scatter, so with one run per building the interval reflects the choice of
buildings only and is too narrow.
"""
from __future__ import annotations

import warnings
from collections.abc import Sequence

import numpy as np

from slam_predict.collect.fidelity import (
    SCATTER_OF,
    THESIS_COLUMNS,
    Bar,
    Comparison,
    sample_std,
)


def resampled(comparison: Comparison, rng: np.random.Generator) -> Comparison:
    """One bootstrap replicate: buildings drawn with replacement, each with its runs drawn with
    replacement and our means recomputed."""
    rows = []
    for i in rng.integers(0, len(comparison.rows), len(comparison.rows)):
        row = dict(comparison.rows[i])
        runs = comparison.per_run.get(row["world"])
        if runs is not None:
            count = len(runs["trans_mean"])
            pick = rng.integers(0, count, count)
            for key in THESIS_COLUMNS:
                row[f"{key}_ours"] = float(np.mean(runs[key][pick]))
            for key, of in SCATTER_OF.items():
                row[f"{key}_ours"] = sample_std(runs[of][pick])
        rows.append(row)
    return Comparison(comparison.name, rows, comparison.per_run)


def bootstrap_intervals(comparison: Comparison, bars: Sequence[Bar], draws: int = 2000,
                        seed: int = 0, level: float = 0.95) -> dict[str, tuple[float, float]]:
    """Bar label → (low, high) central ``level`` interval of its figure over ``draws``
    bootstrap replicates (nan, nan when fewer than 3 buildings or no finite draw)."""
    if len(comparison.rows) < 3 or draws < 1:
        return {bar.label: (float("nan"), float("nan")) for bar in bars}
    rng = np.random.default_rng(seed)
    values = {bar.label: [] for bar in bars}
    with warnings.catch_warnings():   # a replicate may repeat one building: ρ undefined (nan)
        warnings.simplefilter("ignore", RuntimeWarning)
        warnings.filterwarnings("ignore", message="An input array is constant")
        for _ in range(draws):
            replicate = resampled(comparison, rng)
            for bar in bars:
                values[bar.label].append(bar.value(replicate))
    tail = (1.0 - level) / 2.0
    out = {}
    for bar in bars:
        finite = np.array(values[bar.label], float)
        finite = finite[np.isfinite(finite)]
        out[bar.label] = ((float("nan"), float("nan")) if len(finite) == 0 else
                          (float(np.quantile(finite, tail)), float(np.quantile(finite, 1 - tail))))
    return out
