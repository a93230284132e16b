"""Which of two SLAM algorithms is expected to be more accurate on a plan, and how sure that is.

Each model gives, per error component, a value and a prediction interval at confidence c
(90 %: CV+ conformal for the plan-only models, :mod:`slam_predict.learn.conformal`; the
robot-aware models' intervals, :mod:`slam_predict.learn.robot.predict`). The comparison treats
each prediction's interval as its predictive distribution of the building's measured error:

- **Distribution.** The value v is the median; below it the distribution is a normal half of
  scale s_lo, above it one of scale s_hi (each half holds half the mass), with
  s_lo = (v − low) / z and s_hi = (high − v) / z, z = Φ⁻¹((1 + c) / 2) (1.645 at 90 %). Its
  CDF is F(x) = Φ((x − v) / s_lo) for x < v and Φ((x − v) / s_hi) for x ≥ v, so
  F(low) = (1 − c) / 2 and F(high) = (1 + c) / 2: the interval is exactly the distribution's
  central c range, and an asymmetric interval (CV+ bounds, the lower bound clipped at 0) gives
  a skewed distribution. A zero-width side is a point mass at v (s = 0).
- **Probability.** With A and B independent, A is the more accurate where its error is the
  lower: P(A < B) = ∫₀¹ (1 − F_B(Q_A(u))) du, Q_A(u) = v_A + s_A(u) Φ⁻¹(u) being A's quantile
  function (s_A(u) = s_lo below u = ½, s_hi above). :func:`probability_lower` evaluates it by
  the midpoint rule on :data:`QUADRATURE_POINTS` quantiles, both ways round, and returns
  ½ (P(A < B) + 1 − P(B < A)): ties of point masses count half, and the two algorithms'
  probabilities add up to 1 exactly (equal predictions give ½).
- **Independence.** Both models read the same plan, so their errors are likely positively
  correlated; that would narrow the spread of the difference and push the probability away
  from ½. Taking them as independent errs toward "too close to call".
- **Decision rule.** The component is ``trans_mean`` (the mean translational error ε_t).
  An algorithm is named the more accurate when its probability is at least
  :data:`CALL_PROBABILITY` (three to one); otherwise the result is "too close to call". No call
  is made when a model gives no value or no interval for ε_t.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.special import ndtr, ndtri

CALL_PROBABILITY = 0.75     # a call needs P ≥ this for one algorithm
DECIDING_COMPONENT = "trans_mean"
QUADRATURE_POINTS = 4096


@dataclass(frozen=True)
class IntervalDistribution:
    """The predictive distribution of one prediction (module doc): median ``value`` and the
    scales of its lower and upper halves (in the component's unit; 0: a point mass)."""

    value: float
    scale_low: float
    scale_high: float

    @classmethod
    def from_interval(cls, value: float, low: float, high: float,
                      confidence: float) -> IntervalDistribution:
        """The distribution whose central ``confidence`` range is [low, high] (low ≤ value ≤
        high)."""
        if not (0.0 < confidence < 1.0 and low <= value <= high):
            raise ValueError(f"need 0 < confidence < 1 and low <= value <= high, got "
                             f"{confidence}, {low}, {value}, {high}")
        z = float(ndtri(0.5 + confidence / 2.0))
        return cls(float(value), (value - low) / z, (high - value) / z)

    def cdf(self, x: np.ndarray) -> np.ndarray:
        """P(X ≤ x)."""
        x = np.asarray(x, dtype=float)
        offset = x - self.value
        scale = np.where(offset < 0.0, self.scale_low, self.scale_high)
        with np.errstate(divide="ignore", invalid="ignore"):
            smooth = ndtr(offset / scale)
        return np.where(scale > 0.0, smooth, (offset >= 0.0).astype(float))

    def quantile(self, u: np.ndarray) -> np.ndarray:
        """The u-quantiles (0 < u < 1)."""
        u = np.asarray(u, dtype=float)
        scale = np.where(u < 0.5, self.scale_low, self.scale_high)
        return self.value + scale * ndtri(u)


def _p_first_below(a: IntervalDistribution, b: IntervalDistribution) -> float:
    """P(A < B) by the midpoint rule over A's quantiles (ties of point masses count 0)."""
    u = (np.arange(QUADRATURE_POINTS) + 0.5) / QUADRATURE_POINTS
    return float(np.mean(1.0 - b.cdf(a.quantile(u))))


def probability_lower(a: IntervalDistribution, b: IntervalDistribution) -> float:
    """The probability that A's error is the lower one (ties half): module doc."""
    return 0.5 * (_p_first_below(a, b) + 1.0 - _p_first_below(b, a))


def distribution_of(entry: Mapping[str, Any], confidence: float) -> IntervalDistribution | None:
    """The distribution of a reported component (``predict``'s entry: status, value, low,
    high), or None when it has no value or no interval."""
    if entry.get("status") != "ok" or entry.get("value") is None or entry.get("low") is None:
        return None
    return IntervalDistribution.from_interval(entry["value"], entry["low"], entry["high"],
                                              confidence)


def decide(first: str, second: str, entries: Mapping[str, Mapping[str, Any]],
           confidences: Mapping[str, float],
           threshold: float = CALL_PROBABILITY) -> dict[str, Any]:
    """The call between algorithms ``first`` and ``second`` from their ``trans_mean`` entries.

    Returns ``verdict`` (the more accurate algorithm, ``too_close_to_call`` or ``no_call``),
    ``probability`` {algorithm: P(its ε_t is the lower)} (None without a call), the
    ``component``, the ``threshold`` and, for ``no_call``, the ``reason``.
    """
    out: dict[str, Any] = {"component": DECIDING_COMPONENT, "threshold": threshold,
                           "probability": None}
    dists = {name: distribution_of(entries[name], confidences[name])
             for name in (first, second)}
    missing = [name for name, dist in dists.items() if dist is None]
    if missing:
        status = entries[missing[0]].get("status")
        what = "no interval" if status == "ok" else status.replace("_", " ")
        return {**out, "verdict": "no_call",
                "reason": f"{missing[0]}'s {DECIDING_COMPONENT} has no usable prediction "
                          f"({what})"}
    p_first = probability_lower(dists[first], dists[second])
    out["probability"] = {first: p_first, second: 1.0 - p_first}
    if max(p_first, 1.0 - p_first) < threshold:
        return {**out, "verdict": "too_close_to_call"}
    return {**out, "verdict": first if p_first >= threshold else second}
