"""Fitted models as plain arrays, evaluated with numpy alone (no scikit-learn import).

Importing scikit-learn costs 1–2 s per process, more than the whole feature extraction of a
1,500 m² plan. So ``train`` also stores every conformal model whose point and fold models are
linear (coefficients over the features) or tree ensembles (random forest, gradient boosting
with squared loss, monotone boosting) as plain data in ``<component>.plain.json``;
``predict`` evaluates those and unpickles only what has no plain form. Each conversion is
checked numerically against the fitted model on random inputs (:func:`plain_model`), so a
model that does not behave as its plain form claims is never converted.
"""
from __future__ import annotations

from typing import Any

import numpy as np

from slam_predict.learn.intervals import cv_plus_interval, split_interval


def _linear(estimator, n_features: int) -> dict[str, Any] | None:
    coef = getattr(estimator, "coef_", None)
    intercept = getattr(estimator, "intercept_", None)
    if coef is None or intercept is None or np.ndim(intercept) != 0:
        return None
    if np.ndim(coef) == 0:  # SingleFeatureLinear: a slope on feature_index_
        full = np.zeros(n_features)
        full[int(getattr(estimator, "feature_index_", 0))] = float(coef)
        coef = full
    coef = np.asarray(coef, dtype=float)
    if coef.shape != (n_features,):
        return None
    return {"kind": "linear", "coef": coef.tolist(), "intercept": float(intercept)}


def _tree(tree) -> dict[str, list]:
    t = tree.tree_
    return {"feature": t.feature.tolist(), "threshold": t.threshold.tolist(),
            "left": t.children_left.tolist(), "right": t.children_right.tolist(),
            "value": t.value[:, 0, 0].tolist()}


def _ensemble(estimator) -> dict[str, Any] | None:
    trees = getattr(estimator, "estimators_", None)
    if trees is None:
        return None
    name = type(estimator).__name__
    if name == "RandomForestRegressor":
        return {"kind": "trees", "combine": "mean", "base": 0.0, "scale": 1.0,
                "trees": [_tree(t) for t in trees]}
    if name == "GradientBoostingRegressor" and getattr(estimator, "loss", "") == "squared_error":
        base = float(np.ravel(getattr(estimator.init_, "constant_", [np.nan]))[0])
        return {"kind": "trees", "combine": "sum", "base": base,
                "scale": float(estimator.learning_rate), "trees": [_tree(t) for t in trees[:, 0]]}
    if name == "MonotoneBoosting":   # learn/robot/monotone.py: base + rate · Σ trees
        return {"kind": "trees", "combine": "sum", "base": float(estimator.base_),
                "scale": float(estimator.learning_rate), "trees": [_tree(t) for t in trees]}
    return None


def evaluate_model(form: dict[str, Any], X: np.ndarray) -> np.ndarray:
    """Predictions of one plain model at rows ``X`` (n, F)."""
    if form["kind"] == "linear":
        return X @ np.asarray(form["coef"]) + form["intercept"]
    # Trees compare float32 inputs with float64 thresholds, as scikit-learn does.
    X32 = X.astype(np.float32).astype(np.float64)
    total = np.zeros(len(X))
    for tree in form["trees"]:
        feature, threshold = np.asarray(tree["feature"]), np.asarray(tree["threshold"])
        left, right = np.asarray(tree["left"]), np.asarray(tree["right"])
        node = np.zeros(len(X), dtype=int)
        while True:
            inner = left[node] >= 0
            if not inner.any():
                break
            rows = np.flatnonzero(inner)
            go_left = X32[rows, feature[node[rows]]] <= threshold[node[rows]]
            node[rows] = np.where(go_left, left[node[rows]], right[node[rows]])
        total += np.asarray(tree["value"])[node]
    if form["combine"] == "mean":
        total /= len(form["trees"])
    return form["base"] + form["scale"] * total


def _probe(n_features: int, X_check: np.ndarray | None, rng: np.random.Generator):
    """Check inputs: the given rows, jittered copies of them and random rows of many scales."""
    scales = rng.choice([1e-3, 1e-1, 1.0, 1e1, 1e3, 1e5], size=(32, n_features))
    rows = [rng.normal(size=(32, n_features)) * scales]
    if X_check is not None and len(X_check):
        X_check = np.asarray(X_check, dtype=float)
        rows += [X_check, X_check * (1 + 0.05 * rng.normal(size=X_check.shape))]
    return np.vstack(rows)


def plain_model(estimator, n_features: int, rng: np.random.Generator,
                X_check: np.ndarray | None = None) -> dict[str, Any] | None:
    """The plain form of a fitted regressor, or None when it has none or does not match it on
    ``X_check`` (e.g. the training rows) and random inputs."""
    form = _linear(estimator, n_features) or _ensemble(estimator)
    if form is None:
        return None
    probe = _probe(n_features, X_check, rng)
    if not np.allclose(evaluate_model(form, probe), estimator.predict(probe),
                       rtol=1e-9, atol=1e-12):
        return None
    return form


def plain_form(model, n_features: int,
               X_check: np.ndarray | None = None) -> dict[str, Any] | None:
    """Plain data of a fitted ConformalRegressor (point model, calibration), or None."""
    rng = np.random.default_rng(0)
    point = plain_model(model.estimator_, n_features, rng, X_check)
    if point is None:
        return None
    form: dict[str, Any] = {"method": model.method, "confidence": float(model.confidence),
                            "conformity": model.conformity, "floor": float(model.floor_),
                            "point": point}
    if model.method == "split":
        form["quantile"] = float(model.quantile_)
        return form
    folds = [plain_model(m, n_features, rng, X_check) for m in model.fold_estimators_]
    if any(f is None for f in folds):
        return None
    form.update(folds=folds, fold_of=model.fold_of_.tolist(),
                residuals=model.residuals_.tolist())
    return form


def predict_plain(form: dict[str, Any], X: np.ndarray) -> np.ndarray:
    """(n, 3) value, low, high of a :func:`plain_form` at rows ``X``."""
    X = np.atleast_2d(np.asarray(X, dtype=float))
    value = evaluate_model(form["point"], X)
    if form["method"] == "split":
        bounds = split_interval(value, form["quantile"], form["conformity"], form["floor"])
    else:
        fold_pred = np.stack([evaluate_model(f, X) for f in form["folds"]])
        bounds = cv_plus_interval(fold_pred, np.asarray(form["fold_of"], dtype=int),
                                  np.asarray(form["residuals"]), 1.0 - form["confidence"],
                                  form["conformity"], form["floor"])
    return np.column_stack([value, bounds])
