"""Estimators against slow, obviously-correct references."""
from __future__ import annotations

import numpy as np
import pytest
from sklearn.compose import TransformedTargetRegressor
from sklearn.feature_selection import SelectKBest, f_regression
from sklearn.linear_model import ElasticNet, LinearRegression
from sklearn.model_selection import GridSearchCV, KFold
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler

from slam_predict.learn.estimators import (
    ElasticNetGridCV,
    FRegressionVoting,
    SingleFeatureLinear,
    draw_subsets,
    f_scores,
    most_voted,
    selection_ranks,
)


def synthetic(n=60, f=8, seed=0, noise=0.3):
    rng = np.random.default_rng(seed)
    X = rng.normal(size=(n, f))
    y = 3.0 * X[:, 1] - 2.0 * X[:, 4] + noise * rng.normal(size=n)
    return X, y


def test_single_feature_line_equals_polyfit():
    X, y = synthetic()
    model = SingleFeatureLinear(feature=4).fit(X, y)
    slope, intercept = np.polyfit(X[:, 4], y, 1)
    assert model.coef_ == pytest.approx(slope) and model.intercept_ == pytest.approx(intercept)
    np.testing.assert_allclose(model.predict(X), slope * X[:, 4] + intercept)


def test_single_feature_by_name():
    X, y = synthetic(f=5)
    X = X[:, :3]
    named = SingleFeatureLinear("b", feature_names=["a", "b", "c"]).fit(X, y)
    assert named.feature_index_ == 1
    with pytest.raises(ValueError, match="not among the column names"):
        SingleFeatureLinear("d", feature_names=["a", "b", "c"]).fit(X, y)


def test_f_scores_equal_sklearn_including_constant_columns():
    X, y = synthetic()
    X[:, 2] = 5.0
    np.testing.assert_allclose(f_scores(X, y), f_regression(X, y)[0], rtol=1e-10)


def test_votes_equal_literal_select_k_best_loop():
    X, y = synthetic(n=40, f=7, noise=3.0)
    subsets = draw_subsets(len(y), 30, 0.8, np.random.default_rng(3))
    ranks = selection_ranks(X, y, subsets)
    for k in range(1, X.shape[1] + 1):
        votes = np.zeros(X.shape[1], dtype=int)
        for rows in subsets:
            votes += SelectKBest(f_regression, k=k).fit(X[rows], y[rows]).get_support()
        np.testing.assert_array_equal((ranks < k).sum(axis=0), votes)


def test_most_voted_breaks_ties_by_mean_rank():
    ranks = np.array([[0, 1, 2], [1, 0, 2], [0, 2, 1]])
    # K=1: feature 0 has 2 votes; K=2: 0 and 1 have 3 and 2 votes.
    assert list(most_voted(ranks, 1)) == [0]
    assert list(most_voted(ranks, 2)) == [0, 1]


def test_fregression_finds_the_informative_features():
    X, y = synthetic(n=80)
    fixed = FRegressionVoting(k=2, n_subsets=50).fit(X, y)
    assert list(fixed.support_) == [1, 4]
    ols = LinearRegression().fit(X[:, [1, 4]], y)
    np.testing.assert_allclose(fixed.predict(X), ols.predict(X[:, [1, 4]]))
    chosen = FRegressionVoting(n_subsets=30).fit(X, y)
    assert chosen.k_ in (2, 3) and {1, 4} <= set(chosen.support_)
    assert chosen.cv_mse_.shape == (X.shape[1],)


def test_fregression_is_deterministic_for_a_seed():
    X, y = synthetic(noise=4.0)
    a = FRegressionVoting(n_subsets=20, random_state=5).fit(X, y)
    b = FRegressionVoting(n_subsets=20, random_state=5).fit(X, y)
    assert a.k_ == b.k_ and list(a.support_) == list(b.support_)


def test_elasticnet_grid_equals_gridsearch_reference():
    """Same folds and grid as a GridSearchCV over scaler + target-scaled ElasticNet."""
    X, y = synthetic(n=60, f=6, noise=1.5)
    y = 0.01 * y + 0.5  # a target in 'metres' far from unit scale
    ours = ElasticNetGridCV(cv=5, random_state=7).fit(X, y)
    seed = int(np.random.default_rng(7).integers(2 ** 31 - 1))
    folds = KFold(5, shuffle=True, random_state=seed)
    model = make_pipeline(StandardScaler(), TransformedTargetRegressor(
        ElasticNet(max_iter=10000, tol=1e-6), transformer=StandardScaler()))
    grid = {"transformedtargetregressor__regressor__alpha": list(ours.alphas),
            "transformedtargetregressor__regressor__l1_ratio": list(ours.l1_ratios)}
    search = GridSearchCV(model, grid, cv=folds, scoring="neg_mean_squared_error").fit(X, y)
    best = search.best_params_
    assert ours.alpha_ == best["transformedtargetregressor__regressor__alpha"]
    assert ours.l1_ratio_ == best["transformedtargetregressor__regressor__l1_ratio"]
    assert -search.best_score_ == pytest.approx(ours.cv_mse_.min(), rel=1e-4)
    np.testing.assert_allclose(ours.predict(X), search.predict(X), rtol=1e-5, atol=1e-7)


def test_elasticnet_coefficients_are_in_original_units():
    X, y = synthetic(n=60, f=5, noise=0.1)
    X = X * np.array([1, 100, 1, 1, 0.01])
    model = ElasticNetGridCV(alphas=(0.01,), l1_ratios=(1.0,)).fit(X, y)
    np.testing.assert_allclose(model.predict(X), X @ model.coef_ + model.intercept_)
    assert abs(model.coef_[1]) == pytest.approx(0.03, rel=0.05)  # 3 per 100 units
