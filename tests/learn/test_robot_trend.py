"""TrendTailBoosting: plain gradient boosting inside the training range of its trend columns,
the least-squares power law beyond it (checked against numpy's own fits and the booster)."""
from __future__ import annotations

import numpy as np
import pytest
from sklearn.ensemble import GradientBoostingRegressor

from slam_predict.learn.robot.trend import TrendTailBoosting, least_squares_trend, tail


@pytest.fixture(scope="module")
def data():
    rng = np.random.default_rng(5)
    X = np.column_stack([rng.uniform(5.0, 7.5, 300), rng.uniform(0.0, 1.0, 300)])
    y = 0.7 * X[:, 0] + np.sin(6.0 * X[:, 1]) + 0.1 * rng.normal(size=300)
    return X, y


def test_trend_is_least_squares_on_the_given_columns(data):
    X, y = data
    slopes, intercept = least_squares_trend(X[:, [0]], y)
    slope, expected = np.polyfit(X[:, 0], y, 1)
    assert slopes == pytest.approx([slope]) and intercept == pytest.approx(expected)
    none, mean = least_squares_trend(X[:, []], y)
    assert len(none) == 0 and mean == pytest.approx(y.mean())


def test_inside_the_range_it_is_the_booster_beyond_it_the_trend_continues(data):
    X, y = data
    model = TrendTailBoosting((0,), 80, 0.1, 2, 0.8, random_state=3).fit(X, y)
    plain = GradientBoostingRegressor(n_estimators=80, learning_rate=0.1, max_depth=2,
                                      subsample=0.8, random_state=3).fit(X, y)
    np.testing.assert_array_equal(model.predict(X), plain.predict(X))
    assert model.slope_[0] == pytest.approx(np.polyfit(X[:, 0], y, 1)[0])
    edge = np.array([[7.5, 0.3], [5.0, 0.3]])
    far = np.array([[9.5, 0.3], [3.0, 0.3]])   # 2 beyond each end of the range
    step = model.predict(far) - model.predict(edge)
    assert step == pytest.approx([2.0 * model.slope_[0], -2.0 * model.slope_[0]])
    assert model.slope_[0] == pytest.approx(0.7, abs=0.12)   # its sd here: 0.05
    # a column outside the trend stays flat beyond its range, as plain trees do
    assert model.predict([[6.0, 3.0]]) == pytest.approx(model.predict([[6.0, 1.0]]), abs=0.02)


def test_tail_is_zero_inside_and_linear_outside():
    X = np.array([[1.0, 0.0], [3.0, 0.0], [5.0, 9.0], [-1.0, 9.0]])
    out = tail(X, np.array([0]), np.array([2.0]), np.array([0.0]), np.array([4.0]))
    assert out == pytest.approx([0.0, 0.0, 2.0, -2.0])
    assert tail(X, np.array([], dtype=int), np.array([]), np.array([]), np.array([])) \
        == pytest.approx(np.zeros(4))
