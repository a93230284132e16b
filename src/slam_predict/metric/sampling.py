"""Sample sizes from a pilot (thesis §4.2.2–4.2.3): n = ⌈z²·s²/d²⌉, the larger of trans and rot.

z is the two-sided normal z-score of the confidence level (99 % → 2.5758); s² the unbiased
(ddof = 1) variance of the pilot values; d the margin of error. The thesis prints z, not z²; we
use z², the standard formula (the spec says so).
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass

import numpy as np
from scipy.stats import norm

# Relations per run (thesis §4.2.3).
RELATION_PILOT = 500
RELATION_CONFIDENCE = 0.99
RELATION_MARGIN_TRANS = 0.02      # m
RELATION_MARGIN_ROT = 0.002       # rad
# Runs per building (thesis §4.2.2 and §7.2).
RUN_PILOT = 10
RUN_CONFIDENCE = 0.95
RUN_MARGIN_TRANS = 0.03           # m
RUN_MARGIN_ROT = 0.002            # rad


def z_score(confidence: float) -> float:
    """Two-sided z-score z_{α/2} of a confidence level in (0, 1)."""
    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence must be in (0, 1), got {confidence}")
    return float(norm.ppf(1.0 - (1.0 - confidence) / 2.0))


def required_sample_size(std: float, margin: float, confidence: float) -> int:
    """⌈z²·s²/d²⌉ for sample std ``std`` and margin ``margin`` (same unit)."""
    if margin <= 0:
        raise ValueError("margin must be positive")
    if not math.isfinite(std):
        raise ValueError("std must be finite (need at least 2 pilot values)")
    # Round away float noise first so an exact integer quotient is not pushed up by 1 ulp.
    return int(math.ceil(round((z_score(confidence) * std / margin) ** 2, 9)))


@dataclass(frozen=True)
class SampleSizeEstimate:
    """Sample size needed for translation, rotation, and the larger of the two."""

    n_trans: int
    n_rot: int
    std_trans: float
    std_rot: float
    confidence: float
    margin_trans: float
    margin_rot: float

    @property
    def n(self) -> int:
        return max(self.n_trans, self.n_rot)

    def to_dict(self) -> dict:
        return {**asdict(self), "n": self.n}


def estimate_sample_size(trans_values: Sequence[float], rot_values: Sequence[float],
                         margin_trans: float, margin_rot: float,
                         confidence: float) -> SampleSizeEstimate:
    """Sample size for pilot values of the translational (m) and rotational (rad) error."""
    s_t = float(np.std(np.asarray(trans_values, float), ddof=1))
    s_r = float(np.std(np.asarray(rot_values, float), ddof=1))
    return SampleSizeEstimate(required_sample_size(s_t, margin_trans, confidence),
                              required_sample_size(s_r, margin_rot, confidence),
                              s_t, s_r, confidence, margin_trans, margin_rot)


def relation_sample_size(trans_errors, rot_errors, margin_trans: float = RELATION_MARGIN_TRANS,
                         margin_rot: float = RELATION_MARGIN_ROT,
                         confidence: float = RELATION_CONFIDENCE) -> SampleSizeEstimate:
    """Relations needed for a run from pilot per-relation errors (thesis defaults)."""
    return estimate_sample_size(trans_errors, rot_errors, margin_trans, margin_rot, confidence)


@dataclass(frozen=True)
class RunCountDecision:
    """Whether a building needs more runs, and how many in total are estimated."""

    more_needed: bool
    runs_done: int
    runs_required: int
    estimate: SampleSizeEstimate = None

    def to_dict(self) -> dict:
        out = {k: v for k, v in asdict(self).items() if k != "estimate"}
        out["estimate"] = None if self.estimate is None else self.estimate.to_dict()
        return out


def run_count(per_run_trans: Sequence[float], per_run_rot: Sequence[float], *,
              pilot: int = RUN_PILOT, margin_trans: float = RUN_MARGIN_TRANS,
              margin_rot: float = RUN_MARGIN_ROT, confidence: float = RUN_CONFIDENCE,
              max_runs: int = None) -> RunCountDecision:
    """The thesis' stopping rule for the number of runs of one building.

    Fewer than ``pilot`` runs → more needed (required = pilot). Otherwise |R| = ⌈z²·s²/d²⌉ from
    the runs so far (unbiased variance of the per-run ε_t and ε_r), the larger of the two, at
    least ``pilot``; more are needed while |R| > runs done (capped at ``max_runs`` when given).
    """
    done = len(per_run_trans)
    if len(per_run_rot) != done:
        raise ValueError("per-run translational and rotational errors differ in count")
    if done < pilot or done < 2:
        required = max(pilot, 2)
        estimate = None
    else:
        estimate = estimate_sample_size(per_run_trans, per_run_rot, margin_trans, margin_rot,
                                        confidence)
        required = max(pilot, estimate.n)
    if max_runs is not None:
        required = min(required, max_runs)
    return RunCountDecision(required > done, done, required, estimate)

