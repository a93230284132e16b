"""The failure probability of the robot-aware models (learn/robot/failure.py): the plain
logistic form equals scikit-learn's, the Brier score and reliability table match hand
computations, a known relation is recovered, and the shipped model's failure model beats the
base rate with whole buildings held out."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from sklearn.linear_model import LogisticRegression

from slam_predict.learn.robot import failure as fl
from slam_predict.learn.robot.predict import RobotModel

CAMPAIGNS = ("data/campaigns/robots", "data/campaigns/robots_rep3", "data/campaigns/robots_rep4")


@pytest.fixture(scope="module")
def synthetic():
    """Runs of 12 buildings: failure more likely with a short laser (x1) in a large one (x0)."""
    rng = np.random.default_rng(5)
    n = 600
    X = np.column_stack([rng.uniform(200, 2000, n), rng.uniform(3.5, 30, n),
                         rng.uniform(180, 360, n)])
    logit = 1.5 * np.log(X[:, 0] / 600) - 2.5 * np.log(X[:, 1] / 6)
    p = 1 / (1 + np.exp(-logit))
    failed = (rng.uniform(size=n) < p).astype(int)
    groups = np.array([f"b{i % 12}" for i in range(n)])
    return X, failed, groups, p


def test_plain_form_equals_scikit_learn(synthetic):
    X, failed, _, _ = synthetic
    model = fl.fit_failure(X, failed, ["area", "range", "fov"], [0, 1], C=0.5)
    Z = X.copy()
    Z[:, :2] = np.log(Z[:, :2])
    Z = (Z - Z.mean(axis=0)) / Z.std(axis=0)
    reference = LogisticRegression(C=0.5, max_iter=1000).fit(Z, failed)
    assert np.allclose(model.probability(X), reference.predict_proba(Z)[:, 1], atol=1e-6)
    again = fl.FailureModel.from_form(json.loads(json.dumps(model.to_form())))
    assert np.array_equal(again.probability(X), model.probability(X))


def test_a_known_relation_is_recovered_and_beats_the_base_rate(synthetic):
    X, failed, groups, p = synthetic
    model = fl.fit_failure(X, failed, ["area", "range", "fov"], [0, 1], C=1.0)
    assert model.coef[0] > 0 > model.coef[1]           # larger building, shorter laser: worse
    assert np.median(np.abs(model.probability(X) - p)) < 0.05
    ev = fl.evaluate_failure(X, failed, groups, ["area", "range", "fov"], [0, 1])
    assert ev["runs"] == len(failed) and ev["buildings"] == 12
    assert ev["brier"] < 0.8 * ev["brier_base_rate"]
    assert sum(b["runs"] for b in ev["reliability"]) == len(failed)


def test_one_class_gives_a_constant_model():
    X = np.ones((5, 2))
    model = fl.fit_failure(X, np.zeros(5, dtype=int), ["a", "b"], [])
    assert np.allclose(model.probability(X), 1e-3)


def test_an_input_constant_up_to_rounding_does_not_decide_the_probability():
    """One robot in every run: its fov (270° from 4.712389 rad) differs between runs by
    rounding only; a robot at 270.0° exactly must get the same probability as the runs."""
    rng = np.random.default_rng(3)
    area = rng.uniform(200, 2000, 80)
    fov = np.full(80, 270.0000011238746) + rng.choice([0.0, 5.7e-14], 80)
    failed = (rng.uniform(size=80) < 0.4).astype(int)
    model = fl.fit_failure(np.column_stack([area, fov]), failed, ["area", "fov"], [0])
    assert model.scale[1] == 1.0
    trained = model.probability(np.column_stack([area, fov]))
    exact = model.probability(np.column_stack([area, np.full(80, 270.0)]))
    assert np.allclose(trained, exact, atol=1e-6) and 0.2 < exact.mean() < 0.6


def test_brier_and_reliability_by_hand():
    p = np.array([0.0, 0.04, 0.3, 0.5, 0.9, 1.0])
    y = np.array([0, 0, 1, 0, 1, 1])
    assert fl.brier(p, y) == pytest.approx((0 + 0.0016 + 0.49 + 0.25 + 0.01 + 0) / 6)
    table = fl.reliability(p, y, (0.0, 0.1, 0.6, 1.0))
    assert [b["runs"] for b in table] == [2, 2, 2]
    assert table[0]["predicted"] == pytest.approx(0.02) and table[0]["observed"] == 0.0
    assert table[1]["observed"] == 0.5 and table[2]["predicted"] == pytest.approx(0.95)
    assert math.isnan(fl.reliability(p, y, (0.0, 0.01, 0.02, 1.0))[1]["predicted"])


def test_outcome_runs_count_every_run_of_the_campaigns(root):
    runs = fl.outcome_runs([root / c for c in CAMPAIGNS], 30.0)
    assert len(runs) == 336
    assert sum(r.coverage < 0.5 for r in runs) == 34          # the runs learn robots skips
    assert max(r.robot["laser_range_max_m"] for r in runs) <= 30.0


@pytest.fixture(scope="module")
def shipped(root) -> RobotModel:
    return RobotModel.load(root / "models" / "own-robots")


def test_shipped_failure_model_beats_the_base_rate(shipped):
    entry = shipped.failure_entry
    assert entry["coverage_threshold"] == 0.9 and entry["runs"] == 552
    ev = entry["evaluation"]
    assert ev["protocol"] == "leave one building out" and ev["buildings"] == 44
    assert ev["brier"] < ev["brier_base_rate"]
    assert sum(b["runs"] for b in ev["reliability"]) == 552


def test_shipped_failure_probability_rises_as_the_laser_shortens(shipped):
    from slam_predict.features.sightline import curve_columns

    world = shipped.point_worlds[0]
    row = shipped.points[0]
    plan = {n: float(v) for n, v in zip(shipped.names, row, strict=True)}
    plan.update(dict(zip(curve_columns(), shipped.card["sightline_curves"][world],
                         strict=True)))
    robot = {"laser_fov_deg": 270.0, "odom_xy_error": 0.01, "odom_yaw_error": 0.035,
             "laser_resolution_deg": 0.5}
    p = [shipped.failure_probability(plan, dict(robot, laser_range_max_m=r))
         for r in (30.0, 10.0, 3.5)]
    assert all(0.0 <= q <= 1.0 for q in p)
    assert p[0] < p[2]
