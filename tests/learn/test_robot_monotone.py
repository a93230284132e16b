"""MonotoneBoosting: scikit-learn's least-squares gradient boosting when unconstrained, and
monotone in the constrained inputs when it is not (checked on a dense grid)."""
from __future__ import annotations

import numpy as np
import pytest
from sklearn.ensemble import GradientBoostingRegressor

from slam_predict.errors import InputError
from slam_predict.learn.plain import evaluate_model, plain_model
from slam_predict.learn.robot.monotone import MonotoneBoosting, monotonic_vector
from slam_predict.learn.robot.trend import TrendTailBoosting


@pytest.fixture(scope="module")
def noisy():
    """y rises with x0 and falls with x1, buried in noise that unconstrained trees fit."""
    rng = np.random.default_rng(11)
    X = rng.uniform(0.0, 1.0, size=(120, 3))
    y = 0.5 * X[:, 0] - 0.5 * X[:, 1] + np.sin(5.0 * X[:, 2]) + 0.4 * rng.normal(size=120)
    return X, y


def _steps_along(model, X_base: np.ndarray, column: int) -> np.ndarray:
    """Differences of the predictions along a 200-point grid of ``column`` (0–1), every
    other input held at each row of ``X_base``: shape (rows, 199)."""
    grid = np.linspace(0.0, 1.0, 200)
    out = []
    for row in X_base:
        X = np.repeat(row[None, :], len(grid), axis=0)
        X[:, column] = grid
        out.append(np.diff(model.predict(X)))
    return np.array(out)


def test_monotonic_vector_maps_names_and_rejects_unknown_or_contradictory_ones():
    names = ["area", "range", "fov"]
    assert monotonic_vector(names, ["area"], ["range", "fov"]) == [1, -1, -1]
    assert monotonic_vector(names, [], []) is None
    with pytest.raises(InputError, match="gb: speed not among the model inputs"):
        monotonic_vector(names, ["speed"], [], "gb")
    with pytest.raises(InputError, match="area both increasing and decreasing"):
        monotonic_vector(names, ["area"], ["area"])


def test_unconstrained_it_is_scikit_learns_gradient_boosting(noisy):
    X, y = noisy
    # leaves of >= 8 rows: in smaller nodes two inputs can split the rows alike, and the two
    # implementations break such ties in different random orders
    ours = MonotoneBoosting(None, 60, 0.1, 3, 8, 1.0, random_state=0).fit(X, y)
    theirs = GradientBoostingRegressor(n_estimators=60, learning_rate=0.1, max_depth=3,
                                       min_samples_leaf=8, random_state=0).fit(X, y)
    probe = np.random.default_rng(1).uniform(-0.2, 1.2, size=(300, 3))
    np.testing.assert_allclose(ours.predict(probe), theirs.predict(probe), atol=1e-9)


def test_constrained_predictions_never_step_against_their_direction(noisy):
    X, y = noisy
    base_rows = X[:15]
    free = MonotoneBoosting(None, 150, 0.1, 3, 1, 0.8, random_state=2).fit(X, y)
    assert (_steps_along(free, base_rows, 0) < -1e-9).any()   # the noise makes free trees dip
    model = MonotoneBoosting([1, -1, 0], 150, 0.1, 3, 1, 0.8, random_state=2).fit(X, y)
    assert (_steps_along(model, base_rows, 0) >= -1e-12).all()
    assert (_steps_along(model, base_rows, 1) <= 1e-12).all()
    assert (_steps_along(model, base_rows, 2) < -1e-9).any()   # the free input stays free
    # and it still learns the signal: both slopes have the right size on average
    grid = np.linspace(0.05, 0.95, 10)
    rise = [model.predict([[0.95, v, 0.5]])[0] - model.predict([[0.05, v, 0.5]])[0]
            for v in grid]
    assert 0.2 < np.mean(rise) < 0.8


def test_same_seed_same_model_and_its_plain_form_matches(noisy):
    X, y = noisy
    a = MonotoneBoosting([1, 0, 0], 40, 0.1, 2, 3, 0.7, random_state=4).fit(X, y)
    b = MonotoneBoosting([1, 0, 0], 40, 0.1, 2, 3, 0.7, random_state=4).fit(X, y)
    np.testing.assert_array_equal(a.predict(X), b.predict(X))
    form = plain_model(a, 3, np.random.default_rng(0), X)
    assert form is not None
    np.testing.assert_allclose(evaluate_model(form, X), a.predict(X), atol=1e-12)


def test_trend_tail_keeps_the_constraint_sign():
    """A trend column constrained to increase gets slope 0 when its fit points down."""
    rng = np.random.default_rng(3)
    X = np.column_stack([rng.uniform(5.0, 7.0, 200), rng.uniform(0.0, 1.0, 200)])
    y = -0.5 * X[:, 0] + X[:, 1] + 0.05 * rng.normal(size=200)
    model = TrendTailBoosting((0,), 50, 0.1, 2, 0.8, 0, 1, [1, 0]).fit(X, y)
    assert model.slope_ == pytest.approx([0.0])
    assert model.predict([[9.0, 0.5]]) == pytest.approx(model.predict([[7.0, 0.5]]))
    free = TrendTailBoosting((0,), 50, 0.1, 2, 0.8, 0, 1, [0, 1]).fit(X, y)
    assert free.slope_[0] == pytest.approx(-0.5, abs=0.12)   # its sd here: 0.04
