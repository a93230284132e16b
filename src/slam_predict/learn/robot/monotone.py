"""Least-squares gradient boosting whose trees respect monotonic constraints.

The robot-aware models learn from a few dozen buildings and a few dozen robots, so a tree can
split on noise and predict, say, a lower error for a robot with worse odometry. Some
directions are known before any data: a longer or wider laser, a laser that is blind in fewer
directions, smaller odometry error or a smaller building never make GMapping's error larger
on average. :class:`MonotoneBoosting` is squared-loss gradient boosting (as scikit-learn's
``GradientBoostingRegressor``, which has no monotonic constraints) built from
``DecisionTreeRegressor`` stages with ``monotonic_cst``: each stage is monotone in the
constrained inputs, and so is their sum. Measured 2026-12-04 (docs/notes/learning.md).
"""
from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.utils.validation import check_is_fitted, validate_data

from slam_predict.errors import InputError


def monotonic_vector(names: Sequence[str], increasing: Sequence[str],
                     decreasing: Sequence[str], what: str = "monotone") -> list[int] | None:
    """Per input of ``names``: +1 (increasing), −1 (decreasing) or 0; None when no input is
    constrained. An unknown name or a name in both lists is an InputError naming ``what``."""
    unknown = [n for n in (*increasing, *decreasing) if n not in names]
    if unknown:
        raise InputError(f"{what}: {', '.join(unknown)} not among the model inputs "
                         f"({', '.join(names)})")
    both = sorted(set(increasing) & set(decreasing))
    if both:
        raise InputError(f"{what}: {', '.join(both)} both increasing and decreasing")
    if not increasing and not decreasing:
        return None
    return [1 if n in increasing else -1 if n in decreasing else 0 for n in names]


class MonotoneBoosting(RegressorMixin, BaseEstimator):
    """Squared-loss gradient boosting of depth-limited regression trees, each monotone in the
    inputs of ``monotonic_cst`` (+1 increasing, −1 decreasing, 0 free; None: no constraint).

    Stage m fits a tree (squared error, ``max_depth``, ``min_samples_leaf``) to the residuals
    y − f_{m−1}(x) of a random ``subsample`` share of the rows (drawn without replacement, as
    scikit-learn's stochastic boosting), and f_m = f_{m−1} + ``learning_rate`` · tree. f_0 is
    the mean of y. ``random_state`` (int or Generator) seeds the subsamples and the trees.

    Fitted: ``base_`` (f_0), ``estimators_`` (the trees, in order).
    """

    def __init__(self, monotonic_cst: Sequence[int] | None = None, n_estimators: int = 100,
                 learning_rate: float = 0.1, max_depth: int = 2, min_samples_leaf: int = 1,
                 subsample: float = 1.0, random_state=None):
        self.monotonic_cst = monotonic_cst
        self.n_estimators = n_estimators
        self.learning_rate = learning_rate
        self.max_depth = max_depth
        self.min_samples_leaf = min_samples_leaf
        self.subsample = subsample
        self.random_state = random_state

    def fit(self, X, y):
        from sklearn.tree import DecisionTreeRegressor

        X, y = validate_data(self, X, y, y_numeric=True)
        rng = np.random.default_rng(self.random_state)
        n_rows = len(y)
        n_draw = max(1, int(self.subsample * n_rows))
        cst = None if self.monotonic_cst is None else np.asarray(self.monotonic_cst, dtype=int)
        self.base_ = float(np.mean(y))
        fitted = np.full(n_rows, self.base_)
        self.estimators_ = []
        for _ in range(self.n_estimators):
            rows = (np.arange(n_rows) if n_draw >= n_rows
                    else np.sort(rng.choice(n_rows, size=n_draw, replace=False)))
            tree = DecisionTreeRegressor(
                criterion="squared_error", max_depth=self.max_depth,
                min_samples_leaf=self.min_samples_leaf, monotonic_cst=cst,
                random_state=int(rng.integers(2**31 - 1)))
            tree.fit(X[rows], y[rows] - fitted[rows])
            fitted += self.learning_rate * tree.predict(X)
            self.estimators_.append(tree)
        return self

    def predict(self, X):
        check_is_fitted(self)
        X = validate_data(self, X, reset=False)
        total = np.zeros(len(X))
        for tree in self.estimators_:
            total += tree.predict(X)
        return self.base_ + self.learning_rate * total


def boosted_trees(monotonic_cst: Sequence[int] | None, n_estimators: int,
                  learning_rate: float, max_depth: int, min_samples_leaf: int,
                  subsample: float, random_state):
    """The unfitted booster of the robot models: :class:`MonotoneBoosting` with constraints,
    scikit-learn's GradientBoostingRegressor (the same boosting) without."""
    if monotonic_cst is not None:
        return MonotoneBoosting(monotonic_cst, n_estimators, learning_rate, max_depth,
                                min_samples_leaf, subsample, random_state)
    from sklearn.ensemble import GradientBoostingRegressor

    return GradientBoostingRegressor(
        n_estimators=n_estimators, learning_rate=learning_rate, max_depth=max_depth,
        min_samples_leaf=min_samples_leaf, subsample=subsample, random_state=random_state)
