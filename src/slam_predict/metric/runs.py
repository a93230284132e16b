"""Per-building statistics over runs (thesis eqs. 3.6–3.9) and the run-count rule.

Each run contributes its per-run mean absolute relation errors ε_t (m) and ε_r (rad) — what the
thesis' data release averages — and optionally the squared variants (thesis eq. 3.1).

The rules every caller shares (docs/formats.md "Std over runs", docs/explanation.md):

- ``MIN_COVERAGE``: a run that mapped less than this share of the reachable free area is a failed
  exploration, left out of what is learnt from or compared by default.
- ``BUILDING_STD_DDOF`` (0): the std over a building's runs in summary.csv and the plan-only
  models' targets divides by the run count (eqs. 3.7/3.9 divide by |R|; numpy ``std`` in the
  seed study's data release).
- ``SAMPLE_STD_DDOF`` (1): the sample std (n − 1) where a std over a few runs is compared or
  given a chi-square interval: the robot-aware models' design points and the fidelity
  comparison's run-to-run scatter.
"""
from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass

import numpy as np

from slam_predict.metric.kummerle import MetricResult

COMPONENTS = ("trans_mean", "trans_std", "rot_mean", "rot_std")
MIN_COVERAGE = 0.5
BUILDING_STD_DDOF = 0
SAMPLE_STD_DDOF = 1


@dataclass(frozen=True)
class BuildingStatistics:
    """The 4 target components (m, rad), squared variants (m², rad²) and the run count."""

    runs: int
    trans_mean: float
    trans_std: float
    rot_mean: float
    rot_std: float
    trans_sqr_mean: float = math.nan
    trans_sqr_std: float = math.nan
    rot_sqr_mean: float = math.nan
    rot_sqr_std: float = math.nan

    def to_dict(self) -> dict:
        return asdict(self)

    def components(self) -> np.ndarray:
        """(trans_mean, trans_std, rot_mean, rot_std) as an array."""
        return np.array([getattr(self, c) for c in COMPONENTS])


def _mean_std(values: Sequence[float] | None):
    if values is None or len(values) == 0:
        return math.nan, math.nan
    values = np.asarray(values, dtype=float)
    return float(values.mean()), float(values.std(ddof=BUILDING_STD_DDOF))


def sample_std(values) -> float:
    """The sample std (``SAMPLE_STD_DDOF``) of ``values``; NaN under 2 values."""
    values = np.asarray(values, dtype=float)
    return float(values.std(ddof=SAMPLE_STD_DDOF)) if len(values) >= 2 else math.nan


def building_statistics(per_run_trans: Sequence[float], per_run_rot: Sequence[float],
                        per_run_trans_sqr: Sequence[float] | None = None,
                        per_run_rot_sqr: Sequence[float] | None = None) -> BuildingStatistics:
    """Mean and std (ddof 0) over runs of the per-run errors."""
    if len(per_run_trans) != len(per_run_rot):
        raise ValueError("per-run translational and rotational errors differ in count")
    tm, ts = _mean_std(per_run_trans)
    rm, rs = _mean_std(per_run_rot)
    tqm, tqs = _mean_std(per_run_trans_sqr)
    rqm, rqs = _mean_std(per_run_rot_sqr)
    return BuildingStatistics(len(per_run_trans), tm, ts, rm, rs, tqm, tqs, rqm, rqs)


def building_statistics_from_results(results: Iterable[MetricResult]) -> BuildingStatistics:
    """Per-building statistics from the per-run metric results."""
    summaries = [r.summary() for r in results]
    col = lambda name: [s[name] for s in summaries]  # noqa: E731
    return building_statistics(col("trans_mean"), col("rot_mean"), col("trans_sqr_mean"),
                               col("rot_sqr_mean"))

