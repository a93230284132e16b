"""The metric API: statistics of the four series, streaming, serialisation, sampling, yardstick."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from metric_trajgen import perturbed, random_walk

from slam_predict.metric import (
    ErrorKind,
    MetricResult,
    RelationMetric,
    Variant,
    evaluate_against_reference,
    evaluate_all_pairs,
    evaluate_sampled,
)
from slam_predict.metric.relations import random_forward_pairs, relation_errors
from slam_predict.metric.stats import StreamingStatistics, compute_statistics


def test_statistics_of_four_series_hand_computed():
    ref = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]])
    est = np.array([[0.0, 0.0, 0.0], [1.0, 0.3, 0.0], [2.0, 0.0, 0.1]])
    # (0,1): e = (0, .3, 0); (0,2): e = (0, 0, .1); (1,2): δ=(1-0,-.3,.1), δ*=(1,0,0) → (0,-.3,.1)
    metric = RelationMetric(ddof=1).process_data(est, ref, [[0, 1], [0, 2], [1, 2]])
    t = metric.get_statistics(ErrorKind.TRANSLATION, Variant.ABS)
    assert t.mean == pytest.approx(0.2) and t.n == 3
    assert t.std == pytest.approx(np.std([0.3, 0, 0.3], ddof=1))
    assert (t.min, t.max) == pytest.approx((0.0, 0.3))
    tq = metric.get_statistics(ErrorKind.TRANSLATION, Variant.SQR)
    assert tq.mean == pytest.approx(0.06)
    r = metric.get_statistics(ErrorKind.ROTATION)
    assert r.mean == pytest.approx(0.2 / 3)
    rq = metric.get_statistics(ErrorKind.ROTATION, Variant.SQR)
    assert rq.mean == pytest.approx(0.02 / 3)
    # Thesis eq. 3.1: ε = ε_t + ε_r with the squared means.
    assert tq.mean + rq.mean == pytest.approx((0.09 + 0.01 + 0.09 + 0.01) / 3)


def test_streaming_statistics_match_one_pass():
    rng = np.random.default_rng(0)
    values = rng.gamma(2.0, 0.1, 10_001)
    acc = StreamingStatistics(ddof=1)
    for chunk in np.array_split(values, 17):
        acc.update(chunk)
    one = compute_statistics(values, ddof=1)
    got = acc.result()
    for name in ("mean", "std", "min", "max", "rmse"):
        assert getattr(got, name) == pytest.approx(getattr(one, name), rel=1e-12)
    assert got.n == one.n


def test_statistics_edge_cases():
    assert compute_statistics([]).n == 0 and math.isnan(compute_statistics([]).mean)
    single = compute_statistics([2.0], ddof=1)
    assert single.mean == 2.0 and math.isnan(single.std)
    assert compute_statistics([2.0], ddof=0).std == 0.0


def test_chunked_processing_equals_single(trajectories):
    est, ref = trajectories
    pairs = random_forward_pairs(len(ref), 3000, np.random.default_rng(3))
    whole = RelationMetric().process_data(est, ref, pairs).get_result()
    parts = RelationMetric()
    for chunk in np.array_split(pairs, 7):
        parts.process_data(est, ref, chunk)
    for key, stat in whole.stats.items():
        assert parts.get_result().stats[key].mean == pytest.approx(stat.mean, rel=1e-12)
        assert parts.get_result().stats[key].std == pytest.approx(stat.std, rel=1e-10)
    np.testing.assert_array_equal(parts.errors.trans, relation_errors(est, ref, pairs).trans)


def test_backward_pairs_rejected(trajectories):
    est, ref = trajectories
    with pytest.raises(ValueError, match="forward"):
        RelationMetric().process_data(est, ref, [[5, 2]])


def test_result_round_trip_and_table(trajectories):
    est, ref = trajectories
    result = evaluate_against_reference(est, ref, n_pairs=500, seed=0)
    again = MetricResult.from_dict(json.loads(result.to_json()))
    assert again.to_dict() == result.to_dict()
    lines = result.table().splitlines()
    assert [ln.split(" error")[0] for ln in lines[:4]] == [
        "Abs translational", "Sqr translational", "Abs rotational", "Sqr rotational"]
    assert lines[0].endswith(" m") and lines[1].endswith("m^2")
    assert "deg)" in lines[2] and "deg^2)" in lines[3]
    assert lines[4].startswith("N = 500 relations")
    s = result.summary()
    assert s["rot_mean_deg"] == pytest.approx(math.degrees(s["rot_mean"]))
    assert set(s) >= {"trans_mean", "trans_std", "rot_mean", "rot_std", "n"}


def test_yardstick_is_seeded_and_matches_definition(trajectories):
    est, ref = trajectories
    a = evaluate_against_reference(est, ref)
    b = evaluate_against_reference(est, ref, n_pairs=5000, seed=0)
    assert a.to_dict() == b.to_dict() and a.n_relations == 5000
    pairs = random_forward_pairs(len(ref), 5000, np.random.default_rng(0))
    errors = relation_errors(est, ref, pairs)
    assert a.summary()["trans_mean"] == pytest.approx(errors.trans.mean(), rel=1e-12)
    assert a.summary()["rot_std_deg"] == pytest.approx(np.degrees(errors.rot).std(ddof=1), rel=1e-9)
    c = evaluate_against_reference(est, ref, seed=1)
    assert c.summary()["trans_mean"] != a.summary()["trans_mean"]


@pytest.mark.parametrize("sigma", [(0.05, 0.05, 0.02), (0.5, 0.5, 1.5)])
def test_all_pairs_kernel_matches_brute_force(sigma):
    rng = np.random.default_rng(7)
    ref = random_walk(rng, 60)
    est = perturbed(rng, ref, sigma)          # large sigma: rotation errors wrap around ±π
    exact = evaluate_all_pairs(est, ref)
    trans, rot = [], []
    for i in range(60):
        for j in range(i + 1, 60):
            e = relation_errors(est, ref, [[i, j]])
            trans.append(e.trans[0])
            rot.append(e.rot[0])
    assert exact.n_relations == len(trans) == 1770
    series = {"trans_abs": trans, "trans_sqr": np.square(trans), "rot_abs": rot,
              "rot_sqr": np.square(rot)}
    for key, values in series.items():
        want = compute_statistics(values, ddof=1)
        got = exact.stats[key]
        for name in ("mean", "std", "min", "max", "rmse"):
            assert getattr(got, name) == pytest.approx(getattr(want, name), rel=1e-10, abs=1e-14)
        assert got.n == want.n


def test_sampled_evaluation_uses_pilot_sample_size():
    rng = np.random.default_rng(11)
    ref = random_walk(rng, 1500)
    est = perturbed(rng, ref, sigma=(0.01, 0.01, 0.002))
    result = evaluate_sampled(est, ref, np.random.default_rng(0))
    size = result.info["sample_size"]
    assert result.n_relations == size["n"] == max(size["n_trans"], size["n_rot"])
    expected = math.ceil((2.5758293035489 * size["std_trans"] / 0.02) ** 2)
    assert size["n_trans"] == expected
    # The sampled estimate is within a few margins of the exact all-pairs value.
    exact = evaluate_all_pairs(est, ref)
    assert abs(result.summary()["trans_mean"] - exact.summary()["trans_mean"]) < 3 * 0.02
    assert abs(result.summary()["rot_mean"] - exact.summary()["rot_mean"]) < 3 * 0.002


def test_sampled_small_trajectory_uses_all_pairs():
    rng = np.random.default_rng(2)
    ref = random_walk(rng, 30)
    est = perturbed(rng, ref, sigma=(0.3, 0.3, 0.2))
    result = evaluate_sampled(est, ref, np.random.default_rng(0))
    assert result.n_relations == 435 and result.info["selection"].startswith("all")
