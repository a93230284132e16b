"""learn/compare.py: the predictive distribution of an interval and the probability that one
algorithm's error is the lower, against Monte Carlo sampling of the same distributions."""
from __future__ import annotations

import numpy as np
import pytest

from slam_predict.learn.compare import (
    CALL_PROBABILITY,
    IntervalDistribution,
    decide,
    distribution_of,
    probability_lower,
)


def sample(dist: IntervalDistribution, n: int, rng: np.random.Generator) -> np.ndarray:
    """Draws built from the definition: the median, then a fair coin for the half and a
    half-normal |Z| times that half's scale."""
    z = np.abs(rng.standard_normal(n))
    upper = rng.random(n) < 0.5
    return np.where(upper, dist.value + dist.scale_high * z, dist.value - dist.scale_low * z)


def monte_carlo(a, b, rng, n=1_000_000) -> float:
    """P(A < B) + P(A = B) / 2 from n independent draws of each."""
    x, y = sample(a, n, rng), sample(b, n, rng)
    return float(np.mean(x < y) + 0.5 * np.mean(x == y))


def test_the_interval_is_the_central_range_of_its_distribution():
    rng = np.random.default_rng(3)
    for confidence in (0.8, 0.9, 0.95):
        dist = IntervalDistribution.from_interval(0.2, 0.05, 0.5, confidence)
        x = sample(dist, 400_000, rng)
        tail = (1 - confidence) / 2
        assert np.mean(x < 0.05) == pytest.approx(tail, abs=0.002)
        assert np.mean(x > 0.5) == pytest.approx(tail, abs=0.002)
        assert np.median(x) == pytest.approx(0.2, abs=0.002)
        assert dist.cdf(np.array([0.05, 0.2, 0.5])) == pytest.approx([tail, 0.5, 1 - tail])
        u = np.array([0.01, 0.3, 0.5, 0.7, 0.99])
        assert dist.cdf(dist.quantile(u)) == pytest.approx(u)


def test_probability_matches_monte_carlo_on_random_intervals():
    rng = np.random.default_rng(7)
    for _ in range(12):
        pair = []
        for _ in range(2):
            value = rng.uniform(0.05, 0.6)
            low = value * rng.uniform(0.0, 1.0)      # 0: the interval's lower end clipped
            high = value * rng.uniform(1.0, 2.5)
            pair.append(IntervalDistribution.from_interval(value, low, high, 0.9))
        expected = monte_carlo(*pair, rng)
        assert probability_lower(*pair) == pytest.approx(expected, abs=0.003)
        assert probability_lower(*pair) + probability_lower(*pair[::-1]) == pytest.approx(1.0)


def test_equal_predictions_and_point_masses():
    a = IntervalDistribution.from_interval(0.2, 0.1, 0.35, 0.9)
    assert probability_lower(a, a) == pytest.approx(0.5, abs=1e-12)
    point = IntervalDistribution.from_interval(0.2, 0.2, 0.2, 0.9)
    assert probability_lower(point, point) == 0.5
    one_sided = IntervalDistribution.from_interval(0.2, 0.2, 0.4, 0.9)   # a mass ½ at 0.2
    rng = np.random.default_rng(11)
    for other in (a, point, one_sided):
        assert probability_lower(one_sided, other) == pytest.approx(
            monte_carlo(one_sided, other, rng), abs=0.003)
    far = IntervalDistribution.from_interval(0.9, 0.8, 1.0, 0.9)
    assert probability_lower(a, far) > 0.999


def entry(value, low, high, status="ok"):
    return {"status": status, "value": value, "low": low, "high": high, "unit": "m"}


def test_decide_calls_the_lower_error_or_says_too_close():
    conf = {"gmapping": 0.9, "karto": 0.9}
    clear = decide("gmapping", "karto", {"gmapping": entry(0.5, 0.4, 0.6),
                                         "karto": entry(0.2, 0.1, 0.3)}, conf)
    assert clear["verdict"] == "karto" and clear["probability"]["karto"] > 0.99
    assert clear["component"] == "trans_mean" and clear["threshold"] == CALL_PROBABILITY
    close = decide("gmapping", "karto", {"gmapping": entry(0.25, 0.1, 0.4),
                                         "karto": entry(0.22, 0.1, 0.4)}, conf)
    assert close["verdict"] == "too_close_to_call"
    assert 0.5 < close["probability"]["karto"] < CALL_PROBABILITY
    assert sum(close["probability"].values()) == pytest.approx(1.0)
    at = close["probability"]["karto"]
    assert decide("gmapping", "karto", {"gmapping": entry(0.25, 0.1, 0.4),
                                        "karto": entry(0.22, 0.1, 0.4)}, conf,
                  threshold=at)["verdict"] == "karto"


def test_no_call_without_a_usable_prediction():
    conf = {"a": 0.9, "b": 0.9}
    below = entry(None, None, 0.1, status="below_range")
    out = decide("a", "b", {"a": entry(0.2, 0.1, 0.3), "b": below}, conf)
    assert out["verdict"] == "no_call" and out["probability"] is None
    assert "b's trans_mean" in out["reason"] and "below range" in out["reason"]
    out = decide("a", "b", {"a": entry(0.2, None, None), "b": entry(0.2, 0.1, 0.3)}, conf)
    assert out["verdict"] == "no_call" and "no interval" in out["reason"]
    assert distribution_of({"status": "no_model", "value": None, "low": None}, 0.9) is None
    with pytest.raises(ValueError):
        IntervalDistribution.from_interval(0.2, 0.3, 0.4, 0.9)
