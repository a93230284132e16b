"""Sample-size formula, run-count rule and per-building statistics."""
from __future__ import annotations

import math

import numpy as np
import pytest

from slam_predict.metric import (
    MetricResult,
    building_statistics,
    building_statistics_from_results,
    relation_sample_size,
    required_sample_size,
    run_count,
    z_score,
)
from slam_predict.metric.stats import compute_statistics


def test_z_scores():
    assert z_score(0.95) == pytest.approx(1.959963984540054, abs=1e-12)
    assert z_score(0.99) == pytest.approx(2.5758293035489, abs=1e-12)
    with pytest.raises(ValueError):
        z_score(1.0)


def test_sample_size_formula_hand_computed():
    # z² s² / d² with z(99 %) = 2.5758: s = 0.1 m, d = 0.02 m → 6.634 × 25 = 165.87 → 166.
    assert required_sample_size(0.1, 0.02, 0.99) == 166
    # 95 %: s = 0.03, d = 0.03 → z² = 3.8415 → 4.
    assert required_sample_size(0.03, 0.03, 0.95) == 4
    # An exact integer is not rounded up: z = 1.96 ⇒ pick s so that z s / d = 10 exactly.
    s = 10 * 0.01 / z_score(0.95)
    assert required_sample_size(s, 0.01, 0.95) == 100
    assert required_sample_size(0.0, 0.02, 0.99) == 0


def test_relation_sample_size_takes_larger_with_unbiased_variance():
    rng = np.random.default_rng(0)
    trans = rng.gamma(2, 0.05, 500)
    rot = rng.gamma(2, 0.004, 500)
    est = relation_sample_size(trans, rot)
    z2 = z_score(0.99) ** 2
    assert est.n_trans == math.ceil(z2 * np.var(trans, ddof=1) / 0.02 ** 2)
    assert est.n_rot == math.ceil(z2 * np.var(rot, ddof=1) / 0.002 ** 2)
    assert est.n == max(est.n_trans, est.n_rot)


def test_run_count_pilot_then_formula():
    few = run_count([0.2] * 5, [0.01] * 5)
    assert few.more_needed and few.runs_required == 10 and few.estimate is None
    rng = np.random.default_rng(1)
    trans = list(rng.normal(0.3, 0.06, 10))
    rot = list(rng.normal(0.01, 0.002, 10))
    decision = run_count(trans, rot)
    z2 = z_score(0.95) ** 2
    n_t = math.ceil(z2 * np.var(trans, ddof=1) / 0.03 ** 2)
    n_r = math.ceil(z2 * np.var(rot, ddof=1) / 0.002 ** 2)
    assert decision.runs_required == max(10, n_t, n_r)
    assert decision.more_needed == (decision.runs_required > 10)
    # Tight spread: the pilot suffices.
    assert not run_count([0.3 + 0.001 * i for i in range(10)], [0.01] * 10).more_needed
    assert run_count(trans, rot, max_runs=12).runs_required <= 12


def test_run_count_iterates_until_satisfied():
    rng = np.random.default_rng(5)
    trans, rot = [], []
    while run_count(trans, rot).more_needed:
        trans.append(float(rng.normal(0.4, 0.05)))
        rot.append(float(rng.normal(0.01, 0.003)))
    final = run_count(trans, rot)
    assert final.runs_done >= final.runs_required >= 10


def test_building_statistics_ddof0():
    stats = building_statistics([0.1, 0.2, 0.3], [0.01, 0.02, 0.06])
    assert stats.runs == 3
    assert stats.trans_mean == pytest.approx(0.2)
    assert stats.trans_std == pytest.approx(np.std([0.1, 0.2, 0.3]))   # ddof 0, thesis eq. 3.7
    assert stats.rot_std == pytest.approx(np.std([0.01, 0.02, 0.06]))
    np.testing.assert_allclose(stats.components(), [0.2, stats.trans_std, 0.03, stats.rot_std])
    assert math.isnan(stats.trans_sqr_mean)


def _result(trans, rot):
    return MetricResult({"trans_abs": compute_statistics(trans),
                         "trans_sqr": compute_statistics(np.square(trans)),
                         "rot_abs": compute_statistics(rot),
                         "rot_sqr": compute_statistics(np.square(rot))})


def test_building_statistics_from_results():
    runs = [_result([0.1, 0.3], [0.01, 0.03]), _result([0.4, 0.4], [0.02, 0.02])]
    stats = building_statistics_from_results(runs)
    assert stats.trans_mean == pytest.approx(0.3) and stats.trans_std == pytest.approx(0.1)
    assert stats.trans_sqr_mean == pytest.approx((0.05 + 0.16) / 2)


def test_run_count_without_runs_asks_for_the_pilot():
    decision = run_count([], [])
    assert decision.more_needed and (decision.runs_done, decision.runs_required) == (0, 10)
