"""Confidence intervals over runs (metric.intervals): hand-computed values, scipy's own t
interval, and the coverage of both intervals on seeded normal samples."""
import math

import numpy as np
import pytest
from scipy import stats

from slam_predict.metric.intervals import mean_interval, std_interval


def test_hand_computed_values():
    """1, 2, 3, 4: mean 2.5, s² = 5/3; t_{0.975,3} = 3.182, χ²_{0.975,3} = 9.348,
    χ²_{0.025,3} = 0.2158 (printed tables)."""
    m = mean_interval([1, 2, 3, 4])
    half = 3.182 * math.sqrt(5 / 3) / 2
    assert m.value == 2.5 and m.method == "t" and m.n == 4
    assert m.low == pytest.approx(2.5 - half, abs=1e-3)
    assert m.high == pytest.approx(2.5 + half, abs=1e-3)
    s = std_interval([1, 2, 3, 4])
    assert s.value == pytest.approx(math.sqrt(1.25))  # ddof = 0, as summary.csv
    assert s.low == pytest.approx(math.sqrt(5 / 9.348), rel=1e-3)
    assert s.high == pytest.approx(math.sqrt(5 / 0.2158), rel=1e-3)
    assert s.method == "chi-square"


@pytest.mark.parametrize("n", [2, 3, 10, 60])
def test_mean_interval_matches_scipy(n):
    x = np.random.default_rng(n).normal(0.2, 0.05, n)
    ref = stats.ttest_1samp(x, 0.0).confidence_interval(0.95)
    got = mean_interval(x, 0.95)
    assert got.low == pytest.approx(ref.low, rel=1e-12)
    assert got.high == pytest.approx(ref.high, rel=1e-12)
    narrow = mean_interval(x, 0.9)
    assert got.low < narrow.low < narrow.value < narrow.high < got.high


@pytest.mark.parametrize("n", [2, 5, 30])
def test_coverage_on_normal_samples(n):
    """About 95 % of the intervals of 4,000 seeded normal samples hold the true mean / σ."""
    rng = np.random.default_rng(100 + n)
    mu, sigma, trials = 0.3, 0.07, 4000
    hits_mean = hits_std = 0
    for _ in range(trials):
        x = rng.normal(mu, sigma, n)
        m, s = mean_interval(x), std_interval(x)
        hits_mean += m.low <= mu <= m.high
        hits_std += s.low <= sigma <= s.high
    # binomial sd of the share at 95 %: sqrt(0.95·0.05/4000) = 0.0034; allow 4 sd
    assert abs(hits_mean / trials - 0.95) < 0.014
    assert abs(hits_std / trials - 0.95) < 0.014


def test_single_value_has_no_interval_and_bad_input_is_refused():
    one = mean_interval([0.4])
    assert one.value == 0.4 and one.low is None and one.high is None
    assert std_interval([0.4]).value == 0.0 and std_interval([0.4]).low is None
    with pytest.raises(ValueError):
        mean_interval([])
    with pytest.raises(ValueError):
        std_interval([1.0, float("nan")])
    with pytest.raises(ValueError):
        mean_interval([1.0, 2.0], confidence=1.0)
