"""The seed study's regression models as scikit-learn estimators.

* :class:`SingleFeatureLinear` — ordinary least squares on one feature (by index or name).
* :class:`FRegressionVoting` — ``SelectKBest(f_regression)`` votes on random 80 % subsets,
  OLS on the K most voted features; K given or chosen by inner K-fold CV.
* :class:`ElasticNetGridCV` — ElasticNet on standardised features (and target), ``l1_ratio``
  and ``alpha`` chosen by K-fold CV over the thesis' grids, refit on all data.

Hyperparameters are stored as given; fitted attributes end in ``_``; ``fit`` returns self.
The conformal wrapper lives in :mod:`slam_predict.learn.conformal` (re-exported here).
"""
from __future__ import annotations

import warnings
from collections.abc import Sequence

import numpy as np
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.linear_model import ElasticNet, LinearRegression, enet_path
from sklearn.model_selection import KFold
from sklearn.utils.validation import check_is_fitted, validate_data

from slam_predict.learn.conformal import ConformalRegressor  # noqa: F401  (re-export)

THESIS_L1_RATIOS = (0.1, 0.5, 0.7, 0.9, 0.95, 0.99, 1.0)
THESIS_ALPHAS = (0.01, 0.03, 0.05, 0.1, 0.3, 0.5, 1.0, 3.0, 5.0, 10.0, 30.0, 50.0, 100.0)


class SingleFeatureLinear(RegressorMixin, BaseEstimator):
    """OLS regression line ``y = coef_ * x[feature] + intercept_`` on one feature.

    Args:
        feature: column index, or a name looked up in ``feature_names`` (or in the column
            names of a DataFrame passed to ``fit``).
        feature_names: optional column names of X, for a named ``feature``.
    """

    def __init__(self, feature=0, feature_names: Sequence[str] | None = None):
        self.feature = feature
        self.feature_names = feature_names

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.regressor_tags.poor_score = True  # one feature cannot fit a many-feature target
        return tags

    def _resolve(self) -> int:
        if isinstance(self.feature, str):
            names = self.feature_names
            if names is None:
                names = getattr(self, "feature_names_in_", None)
            if names is None or self.feature not in list(names):
                raise ValueError(f"feature {self.feature!r} not among the column names")
            index = list(names).index(self.feature)
        else:
            index = int(self.feature)
        if not 0 <= index < self.n_features_in_:
            raise ValueError(f"feature index {index} out of range for "
                             f"{self.n_features_in_} features")
        return index

    def fit(self, X, y):
        X, y = validate_data(self, X, y, y_numeric=True)
        self.feature_index_ = self._resolve()
        x = X[:, self.feature_index_]
        x_mean, y_mean = x.mean(), y.mean()
        var = float(((x - x_mean) ** 2).sum())
        cov = float(((x - x_mean) * (y - y_mean)).sum())
        self.coef_ = cov / var if var > 0 else 0.0
        self.intercept_ = float(y_mean - self.coef_ * x_mean)
        return self

    def predict(self, X):
        check_is_fitted(self)
        X = validate_data(self, X, reset=False)
        return self.coef_ * X[:, self.feature_index_] + self.intercept_

    @property
    def support_(self) -> np.ndarray:
        """Indices of the features the model uses."""
        check_is_fitted(self)
        return np.array([self.feature_index_])


def f_scores(X: np.ndarray, y: np.ndarray) -> np.ndarray:
    """F-scores of ``f_regression`` (default ``force_finite``) for a batch of row subsets.

    ``X`` is (..., m, F) and ``y`` (..., m); returns (..., F). As scikit-learn: F = r²/(1 − r²)
    · (m − 2) with r the Pearson correlation; constant columns score 0, perfectly correlated
    ones the largest float. Vectorised because scikit-learn's input checks dominate the cost
    of thousands of tiny calls.
    """
    xc = X - X.mean(axis=-2, keepdims=True)
    yc = y - y.mean(axis=-1, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        corr = np.einsum("...mf,...m->...f", xc, yc) / np.sqrt(
            (xc ** 2).sum(axis=-2) * (yc ** 2).sum(axis=-1)[..., None])
        r2 = corr ** 2
        scores = r2 / (1.0 - r2) * (X.shape[-2] - 2)
    scores = np.where(np.isnan(scores), 0.0, scores)
    return np.where(np.isinf(scores), np.finfo(float).max, scores)


def selection_ranks(X: np.ndarray, y: np.ndarray, subsets: np.ndarray) -> np.ndarray:
    """(n_subsets, F) rank of each feature (0 = best) by F-score on each row subset.

    Same order as ``SelectKBest``: feature f is among the best K iff its rank < K (stable
    ascending sort of the scores, best K taken from the end).
    """
    n_features = X.shape[1]
    scores = f_scores(X[subsets], y[subsets])  # (n_subsets, F)
    order = np.argsort(scores, axis=1, kind="mergesort")[:, ::-1]
    ranks = np.empty_like(order)
    np.put_along_axis(ranks, order, np.arange(n_features)[None, :].repeat(len(order), 0), 1)
    return ranks


def ols_predict(X: np.ndarray, y: np.ndarray, X_new: np.ndarray) -> np.ndarray:
    """Predictions at ``X_new`` of least squares with intercept fitted on (X, y) (min-norm)."""
    x_mean, y_mean = X.mean(axis=0), y.mean()
    coef = np.linalg.lstsq(X - x_mean, y - y_mean, rcond=None)[0]
    return (X_new - x_mean) @ coef + y_mean


def draw_subsets(n_samples: int, n_subsets: int, fraction: float,
                 rng: np.random.Generator) -> np.ndarray:
    """(n_subsets, m) row indices, each row a random subset of round(fraction·n) rows."""
    size = min(n_samples, max(2, int(round(fraction * n_samples))))
    return np.array([np.sort(rng.permutation(n_samples)[:size]) for _ in range(n_subsets)])


def most_voted(ranks: np.ndarray, k: int) -> np.ndarray:
    """Indices of the ``k`` features selected most often among the best ``k`` per subset.

    Ties are broken by the mean rank over all subsets, then by the lower index.
    """
    votes = (ranks < k).sum(axis=0)
    order = np.lexsort((np.arange(ranks.shape[1]), ranks.mean(axis=0), -votes))
    return np.sort(order[:k])


class FRegressionVoting(RegressorMixin, BaseEstimator):
    """OLS on the K features most often in ``SelectKBest(f_regression, k=K)`` of random subsets.

    For each candidate K the best-K features are voted on ``n_subsets`` random
    ``subset_fraction`` subsets of the training rows (the same subsets for every K: a feature's
    F-score rank on a subset does not depend on K). With ``k=None`` K is chosen by ``cv``-fold
    cross-validation (minimum mean squared error; ties → smaller K) among 1..``max_k``.

    Args:
        k: number of features, or None to choose it by CV.
        max_k: largest K tried (None = all features).
        n_subsets, subset_fraction: the voting subsets (thesis: 100 and 0.8).
        cv: folds of the inner cross-validation.
        random_state: seed (int) or numpy Generator for subsets and folds.
    """

    def __init__(self, k: int | None = None, max_k: int | None = None,
                 n_subsets: int = 100, subset_fraction: float = 0.8, cv: int = 5,
                 random_state=0):
        self.k = k
        self.max_k = max_k
        self.n_subsets = n_subsets
        self.subset_fraction = subset_fraction
        self.cv = cv
        self.random_state = random_state

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.regressor_tags.poor_score = self.k is not None or self.max_k is not None
        return tags

    def _candidate_ks(self, n_features: int) -> np.ndarray:
        if self.k is not None:
            if not 1 <= int(self.k) <= n_features:
                raise ValueError(f"k={self.k} must lie in 1..{n_features}")
            return np.array([int(self.k)])
        top = n_features if self.max_k is None else min(int(self.max_k), n_features)
        return np.arange(1, max(top, 1) + 1)

    def _vote(self, X, y, rng) -> np.ndarray:
        subsets = draw_subsets(len(y), self.n_subsets, self.subset_fraction, rng)
        return selection_ranks(X, y, subsets)

    def _cv_errors(self, X, y, ks, rng) -> np.ndarray:
        folds = KFold(min(self.cv, len(y)), shuffle=True,
                      random_state=int(rng.integers(2 ** 31 - 1)))
        errors = np.zeros(len(ks))
        for train, test in folds.split(X):
            ranks = self._vote(X[train], y[train], rng)
            for i, k in enumerate(ks):
                cols = most_voted(ranks, k)
                errors[i] += ((ols_predict(X[train][:, cols], y[train], X[test][:, cols])
                               - y[test]) ** 2).sum()
        return errors / len(y)

    def fit(self, X, y):
        X, y = validate_data(self, X, y, y_numeric=True, ensure_min_samples=2)
        rng = np.random.default_rng(self.random_state)
        ks = self._candidate_ks(X.shape[1])
        if len(ks) > 1:
            if len(y) < 4:
                raise ValueError(f"choosing k by CV needs at least 4 samples, n_samples={len(y)}")
            self.cv_mse_ = self._cv_errors(X, y, ks, rng)
            self.k_ = int(ks[int(np.argmin(self.cv_mse_))])
        else:
            self.k_ = int(ks[0])
        ranks = self._vote(X, y, rng)
        self.votes_ = (ranks < self.k_).sum(axis=0)
        self.support_ = most_voted(ranks, self.k_)
        self.ols_ = LinearRegression().fit(X[:, self.support_], y)
        self.coef_ = np.zeros(X.shape[1])
        self.coef_[self.support_] = self.ols_.coef_
        self.intercept_ = float(self.ols_.intercept_)
        return self

    def predict(self, X):
        check_is_fitted(self)
        X = validate_data(self, X, reset=False)
        return self.ols_.predict(X[:, self.support_])


class ElasticNetGridCV(RegressorMixin, BaseEstimator):
    """ElasticNet on standardised features, (l1_ratio, alpha) chosen by K-fold CV on a grid.

    Each fold standardises X (and, with ``scale_target``, y) on its own training part, so the
    choice sees no validation data; the pair with the lowest mean squared error in y's units
    wins (ties → larger alpha). The final model is refit on all rows. ``coef_`` and
    ``intercept_`` are expressed in the original units of X and y.

    Args:
        l1_ratios, alphas: the grids (thesis values by default).
        cv: number of folds.
        scale_target: divide y by its standard deviation, so one alpha grid suits targets of
            any unit (m or rad); without it, alpha acts on y's raw scale.
        max_iter, tol: coordinate-descent limits.
        random_state: seed (int) or numpy Generator for the fold shuffle.
    """

    def __init__(self, l1_ratios: Sequence[float] = THESIS_L1_RATIOS,
                 alphas: Sequence[float] = THESIS_ALPHAS, cv: int = 5, scale_target: bool = True,
                 max_iter: int = 10000, tol: float = 1e-6, random_state=0):
        self.l1_ratios = l1_ratios
        self.alphas = alphas
        self.cv = cv
        self.scale_target = scale_target
        self.max_iter = max_iter
        self.tol = tol
        self.random_state = random_state

    def _standardise(self, X, y):
        x_mean, x_std = X.mean(axis=0), X.std(axis=0)
        x_std = np.where(x_std > 0, x_std, 1.0)
        y_mean = y.mean()
        y_std = y.std() if self.scale_target else 1.0
        y_std = y_std if y_std > 0 else 1.0
        return x_mean, x_std, y_mean, y_std

    def _path_errors(self, X, y, train, test, alphas) -> np.ndarray:
        x_mean, x_std, y_mean, y_std = self._standardise(X[train], y[train])
        Xs = np.asfortranarray((X[train] - x_mean) / x_std)
        ys = np.ascontiguousarray((y[train] - y_mean) / y_std)
        Xv = (X[test] - x_mean) / x_std
        errors = np.empty((len(self.l1_ratios), len(alphas)))
        for i, l1 in enumerate(self.l1_ratios):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                _, coefs, _ = enet_path(Xs, ys, l1_ratio=l1, alphas=alphas,
                                        max_iter=self.max_iter, tol=self.tol,
                                        check_input=False)
            pred = y_mean + y_std * (Xv @ coefs)  # (n_test, n_alphas)
            errors[i] = ((pred - y[test][:, None]) ** 2).sum(axis=0)
        return errors

    def fit(self, X, y):
        X, y = validate_data(self, X, y, y_numeric=True, ensure_min_samples=2)
        alphas = np.sort(np.asarray(self.alphas, dtype=float))[::-1]
        seed = int(np.random.default_rng(self.random_state).integers(2 ** 31 - 1))
        folds = KFold(min(self.cv, len(y)), shuffle=True, random_state=seed)
        errors = sum(self._path_errors(X, y, tr, te, alphas) for tr, te in folds.split(X))
        self.cv_mse_ = errors / len(y)
        i, j = np.unravel_index(np.argmin(self.cv_mse_), self.cv_mse_.shape)
        self.l1_ratio_, self.alpha_ = float(self.l1_ratios[i]), float(alphas[j])
        x_mean, x_std, y_mean, y_std = self._standardise(X, y)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            self.enet_ = ElasticNet(alpha=self.alpha_, l1_ratio=self.l1_ratio_,
                                    max_iter=self.max_iter, tol=self.tol)
            self.enet_.fit((X - x_mean) / x_std, (y - y_mean) / y_std)
        self.n_iter_ = int(self.enet_.n_iter_)
        self.coef_ = self.enet_.coef_ * y_std / x_std
        self.intercept_ = float(y_mean + y_std * self.enet_.intercept_ - self.coef_ @ x_mean)
        self.support_ = np.flatnonzero(self.coef_)
        return self

    def predict(self, X):
        check_is_fitted(self)
        X = validate_data(self, X, reset=False)
        return X @ self.coef_ + self.intercept_
