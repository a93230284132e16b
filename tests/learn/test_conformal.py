"""Conformal intervals: quantile rule, CV+ against a per-point reference, empirical coverage."""
from __future__ import annotations

import numpy as np
import pytest
from sklearn.linear_model import LinearRegression

from slam_predict.learn.conformal import ConformalRegressor
from slam_predict.learn.intervals import conformal_rank, upper_quantile


def test_conformal_rank():
    assert conformal_rank(9, 0.1) == 9
    assert conformal_rank(8, 0.1) == 9  # > n: the interval is infinite
    assert conformal_rank(43, 0.1) == 40
    assert upper_quantile(np.arange(8.0), 0.1) == np.inf
    assert upper_quantile(np.arange(1.0, 10.0), 0.1) == 9.0


def data(n, seed, hetero=False):
    rng = np.random.default_rng(seed)
    X = rng.uniform(0, 10, size=(n, 2))
    noise = rng.normal(size=n) * (0.2 * X[:, 0] if hetero else 1.0)
    return X, 2.0 * X[:, 0] - X[:, 1] + noise


def test_cv_plus_matches_a_per_point_reference():
    X, y = data(30, 1)
    model = ConformalRegressor(LinearRegression(), cv=5).fit(X, y)
    X_new = data(4, 2)[0]
    got = model.predict_interval(X_new)
    for j, x in enumerate(X_new):
        lows, highs = [], []
        for i in range(len(y)):
            fold_model = model.fold_estimators_[model.fold_of_[i]]
            pred = fold_model.predict(x[None])[0]
            lows.append(pred - model.residuals_[i])
            highs.append(pred + model.residuals_[i])
        n = len(y)
        k = int(np.ceil(0.9 * (n + 1)))
        assert got[j, 1] == pytest.approx(sorted(highs)[k - 1])
        assert got[j, 0] == pytest.approx(sorted(lows)[n - k])


@pytest.mark.parametrize("method,conformity", [("cv_plus", "absolute"), ("split", "absolute"),
                                               ("cv_plus", "scaled")])
def test_empirical_coverage_near_nominal(method, conformity):
    covered = []
    for seed in range(20):
        X, y = data(60, seed, hetero=conformity == "scaled")
        model = ConformalRegressor(LinearRegression(), method=method, conformity=conformity,
                                   random_state=seed).fit(X, y)
        Xt, yt = data(200, 1000 + seed, hetero=conformity == "scaled")
        low, high = model.predict_interval(Xt).T
        covered.append(np.mean((low <= yt) & (yt <= high)))
    assert 0.85 <= np.mean(covered) <= 0.97


def test_point_prediction_comes_from_model_fitted_on_all_rows():
    X, y = data(40, 3)
    model = ConformalRegressor(LinearRegression()).fit(X, y)
    np.testing.assert_allclose(model.predict(X), LinearRegression().fit(X, y).predict(X))


def test_bad_parameters():
    X, y = data(20, 0)
    with pytest.raises(ValueError, match="method"):
        ConformalRegressor(method="jackknife").fit(X, y)
    with pytest.raises(ValueError, match="confidence"):
        ConformalRegressor(confidence=1.5).fit(X, y)


@pytest.mark.parametrize("method", ["cv_plus", "split"])
def test_plain_form_reproduces_the_fitted_model(method):
    from sklearn.ensemble import GradientBoostingRegressor, RandomForestRegressor

    from slam_predict.learn.estimators import (
        ElasticNetGridCV,
        FRegressionVoting,
        SingleFeatureLinear,
    )
    from slam_predict.learn.plain import plain_form, predict_plain

    X, y = data(40, 4)
    X_new = np.vstack([data(7, 5)[0], X[:5]])
    for base in (SingleFeatureLinear(1), FRegressionVoting(n_subsets=10),
                 ElasticNetGridCV(cv=3), LinearRegression(),
                 RandomForestRegressor(n_estimators=10, min_samples_leaf=2, random_state=0),
                 GradientBoostingRegressor(n_estimators=20, max_depth=2, subsample=0.8,
                                           random_state=0)):
        model = ConformalRegressor(base, method=method, conformity="scaled").fit(X, y)
        form = plain_form(model, X.shape[1], X)
        assert form is not None, base
        got = predict_plain(form, X_new)
        np.testing.assert_allclose(got[:, 0], model.predict(X_new), rtol=1e-9)
        np.testing.assert_allclose(got[:, 1:], model.predict_interval(X_new), rtol=1e-9)


def test_models_without_plain_form_are_not_converted():
    from sklearn.neighbors import KNeighborsRegressor

    from slam_predict.learn.plain import plain_form

    X, y = data(40, 4)
    knn = ConformalRegressor(KNeighborsRegressor(3)).fit(X, y)
    assert plain_form(knn, X.shape[1], X) is None
