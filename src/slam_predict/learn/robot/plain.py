"""Robot-aware models as plain arrays, evaluated with numpy alone (no scikit-learn import).

Importing scikit-learn to unpickle a model costs 1.5–2 s per process, more than the feature
extraction of a 1,500 m² plan (``predict --robot`` has 3 s). So :mod:`train` also
stores every fitted :class:`~slam_predict.learn.robot.models.ComponentModel` as plain data in
``<component>.plain.json`` ({model kind: form}): its offset, CV+ calibration (folds,
residuals) and, for the model fitted on every row and each fold model, the pipeline —

- ``log_columns`` / ``log_floor``: the input columns taken as their log (values raised to the
  floor first), as :class:`~slam_predict.learn.robot.models.PositiveLog`;
- ``scale``: StandardScaler's ``mean`` and ``scale`` (Gaussian process only), or None;
- ``model``: a linear form (elasticnet: coefficients and intercept over its inputs), trees
  (gradient boosting: :mod:`slam_predict.learn.plain`; trend boosting adds ``tail``, its
  power-law slopes past the training range: :mod:`slam_predict.learn.robot.trend`) or a
  Gaussian process: kernel C · Matern(ν, one length scale per input) + White with a
  normalised target, whose mean at x is ``y_std · Σ_i C·k(x, x_i)·α_i + y_mean`` (x_i the
  training inputs, α the dual coefficients; the white noise does not enter a
  cross-covariance).

:func:`plain_component` checks each conversion against the fitted pipelines on the training
rows, jittered copies and random rows around them (to 1e-9 on the log scale, i.e. relative
1e-9 of the value); a model that does not match keeps only its joblib form.
:class:`LogScaleModel` holds the prediction and interval maths both forms share.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from slam_predict.learn.intervals import cv_plus_interval

MEANS = ("trans_mean", "rot_mean")
STDS = ("trans_std", "rot_std")
TOLERANCE = 1e-9   # plain vs fitted, on the log scale (absolute) and relative
GP_KERNEL = ("Sum", "Product", "ConstantKernel", "WhiteKernel")


def is_std(component: str) -> bool:
    """True for the run-to-run standard deviations."""
    return component in STDS


def chi2_log_bias(dof: np.ndarray | float) -> np.ndarray:
    """b(ν) = E[log(χ²_ν / ν)] = ψ(ν/2) + log(2/ν) (−1.27 for ν = 1, → 0 for large ν)."""
    from scipy.special import digamma

    dof = np.asarray(dof, dtype=float)
    return digamma(dof / 2.0) + np.log(2.0 / dof)


class LogScaleModel:
    """Prediction and CV+ interval of a component model from its regressors' log-scale
    outputs. Subclasses set ``component``, ``offset``, ``estimator``, ``fold_estimators``,
    ``calibration_fold``, ``residuals`` and implement :meth:`evaluate`."""

    component: str
    offset: float
    estimator: Any
    fold_estimators: list
    calibration_fold: np.ndarray
    residuals: np.ndarray

    def evaluate(self, regressor, X: np.ndarray) -> np.ndarray:
        """The raw log-scale output of one fitted regressor (pipeline) at rows ``X``."""
        raise NotImplementedError

    def predict_log(self, X: np.ndarray) -> np.ndarray:
        """The model's log-scale output (means: log of the point mean; stds: log σ²)."""
        return np.asarray(self.evaluate(self.estimator, np.atleast_2d(X))) + self.offset

    def predict(self, X: np.ndarray) -> np.ndarray:
        """Predicted values, m or rad: the point mean, or the run-to-run std σ."""
        out = self.predict_log(X)
        return np.exp(out / 2.0) if is_std(self.component) else np.exp(out)

    def interval(self, X: np.ndarray, confidence: float = 0.9,
                 runs: int | np.ndarray = 2) -> np.ndarray:
        """(n, 2) CV+ bounds, m or rad: of the point mean, or (stds) of the sample std of a
        point measured over ``runs`` runs (≥ 2; per row or one for all)."""
        from slam_predict.errors import InputError

        if not 0.0 < confidence < 1.0:
            raise InputError(f"confidence must lie in (0, 1), got {confidence!r}")
        X = np.atleast_2d(X)
        fold_pred = np.stack([np.asarray(self.evaluate(m, X)) + self.offset
                              for m in self.fold_estimators])
        log_bounds = cv_plus_interval(fold_pred, self.calibration_fold, self.residuals,
                                      1.0 - confidence, "absolute", 1.0)
        if not is_std(self.component):
            return np.exp(log_bounds)
        runs = np.broadcast_to(np.asarray(runs, dtype=float), (len(X),))
        if np.any(runs < 2):
            raise InputError("a std interval needs 2 or more runs")
        shift = chi2_log_bias(runs - 1)[:, None]
        return np.exp((log_bounds + shift) / 2.0)


# ----------------------------------------------------------------------------- evaluation

def _matern(dists: np.ndarray, nu: float | None) -> np.ndarray:
    """scikit-learn's Matern (RBF for nu None) of scaled Euclidean distances."""
    if nu is None:
        return np.exp(-0.5 * dists ** 2)
    if nu == 0.5:
        return np.exp(-dists)
    if nu == 1.5:
        k = dists * math.sqrt(3)
        return (1.0 + k) * np.exp(-k)
    if nu == 2.5:
        k = dists * math.sqrt(5)
        return (1.0 + k + k ** 2 / 3.0) * np.exp(-k)
    from scipy.special import gamma, kv

    k = dists.copy()
    k[k == 0.0] += np.finfo(float).eps
    tmp = math.sqrt(2 * nu) * k
    out = np.full(k.shape, (2 ** (1.0 - nu)) / gamma(nu))
    return out * tmp ** nu * kv(nu, tmp)


def _gaussian_process(form: dict[str, Any], X: np.ndarray) -> np.ndarray:
    scale = np.asarray(form["length_scale"])
    a, b = X / scale, np.asarray(form["X_train"]) / scale
    if form["nu"] is None:   # RBF: scikit-learn squares no root
        sq = ((a[:, None, :] - b[None, :, :]) ** 2).sum(axis=2)
        kernel = np.exp(-0.5 * sq)
    else:
        dists = np.sqrt(((a[:, None, :] - b[None, :, :]) ** 2).sum(axis=2))
        kernel = _matern(dists, form["nu"])
    mean = (form["constant"] * kernel) @ np.asarray(form["alpha"])
    return form["y_std"] * mean + form["y_mean"]


def tail(X: np.ndarray, columns: np.ndarray, slope: np.ndarray, low: np.ndarray,
         high: np.ndarray) -> np.ndarray:
    """Trend boosting's extrapolation (:mod:`slam_predict.learn.robot.trend`):
    Σ_c slope_c · (x_c − clip(x_c, low_c, high_c)) per row of ``X``, 0 inside the range."""
    if len(columns) == 0:
        return np.zeros(len(X))
    values = np.asarray(X, dtype=float)[:, columns]
    return (values - np.clip(values, low, high)) @ np.asarray(slope, dtype=float)


def evaluate_regressor(form: dict[str, Any], X: np.ndarray) -> np.ndarray:
    """Output of one plain regressor at its (transformed) inputs ``X``."""
    if form["kind"] == "gaussian_process":
        return _gaussian_process(form, X)
    from slam_predict.learn.plain import evaluate_model

    out = evaluate_model(form, X)
    if form.get("tail"):
        t = form["tail"]
        out = out + tail(X, np.asarray(t["columns"], dtype=int), t["slope"], t["low"], t["high"])
    return out


def evaluate_pipeline(form: dict[str, Any], X: np.ndarray) -> np.ndarray:
    """Output of a plain pipeline (log columns → [scaling →] regressor) at raw rows ``X``."""
    X = np.array(X, dtype=float)
    columns = np.asarray(form["log_columns"], dtype=int)
    if len(columns):
        X[:, columns] = np.log(np.maximum(X[:, columns], np.asarray(form["log_floor"])))
    if form["scale"] is not None:
        X = (X - np.asarray(form["scale"]["mean"])) / np.asarray(form["scale"]["scale"])
    return evaluate_regressor(form["model"], X)


def _arrays(form: dict[str, Any]) -> dict[str, Any]:
    """A pipeline form with its numeric lists as arrays (converted once, on loading)."""
    out = dict(form, log_columns=np.asarray(form["log_columns"], dtype=int),
               log_floor=np.asarray(form["log_floor"], dtype=float))
    if out["scale"] is not None:
        out["scale"] = {k: np.asarray(v, dtype=float) for k, v in out["scale"].items()}
    model = dict(out["model"])
    if model["kind"] == "gaussian_process":
        for key in ("length_scale", "X_train", "alpha"):
            model[key] = np.asarray(model[key], dtype=float)
    elif model["kind"] == "trees":
        model["trees"] = [{k: np.asarray(v) for k, v in tree.items()}
                          for tree in model["trees"]]
        if model.get("tail"):
            model["tail"] = {k: np.asarray(v) for k, v in model["tail"].items()}
    else:
        model["coef"] = np.asarray(model["coef"], dtype=float)
    out["model"] = model
    return out


@dataclass
class PlainComponentModel(LogScaleModel):
    """A component model from its plain form (same predictions as the fitted one)."""

    component: str
    kind: str
    names: list[str]
    estimator: dict = field(default_factory=dict)
    fold_estimators: list = field(default_factory=list)
    calibration_fold: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    residuals: np.ndarray = field(default_factory=lambda: np.zeros(0))
    offset: float = 0.0

    def evaluate(self, regressor, X: np.ndarray) -> np.ndarray:
        return evaluate_pipeline(regressor, X)

    @classmethod
    def from_form(cls, form: dict[str, Any]) -> PlainComponentModel:
        """The model of a :func:`plain_component` form (as read back from JSON)."""
        return cls(form["component"], form["kind"], list(form["names"]),
                   _arrays(form["estimator"]), [_arrays(f) for f in form["fold_estimators"]],
                   np.asarray(form["calibration_fold"], dtype=int),
                   np.asarray(form["residuals"], dtype=float), float(form["offset"]))


# ----------------------------------------------------------------------------- conversion

def _gp_form(gp, n_features: int) -> dict[str, Any] | None:
    """The plain form of a fitted GaussianProcessRegressor whose kernel is C · Matern (or
    RBF) + White, else None."""
    kernel = getattr(gp, "kernel_", None)
    if kernel is None or type(kernel).__name__ != GP_KERNEL[0]:
        return None
    product, white = kernel.k1, kernel.k2
    if type(product).__name__ != GP_KERNEL[1] or type(white).__name__ != GP_KERNEL[3] \
            or type(product.k1).__name__ != GP_KERNEL[2]:
        return None
    shape = product.k2
    if type(shape).__name__ not in ("Matern", "RBF"):
        return None
    nu = float(shape.nu) if type(shape).__name__ == "Matern" else None
    nu = None if nu is not None and math.isinf(nu) else nu
    scale = np.broadcast_to(np.atleast_1d(np.asarray(shape.length_scale, dtype=float)),
                            (n_features,))
    return {"kind": "gaussian_process", "constant": float(product.k1.constant_value),
            "nu": nu, "length_scale": scale.tolist(),
            "X_train": np.asarray(gp.X_train_, dtype=float).tolist(),
            "alpha": np.ravel(gp.alpha_).astype(float).tolist(),
            "y_mean": float(np.ravel(gp._y_train_mean)[0]),
            "y_std": float(np.ravel(gp._y_train_std)[0])}


def _trend_form(regressor, X_model: np.ndarray,
                rng: np.random.Generator) -> dict[str, Any] | None:
    """The plain form of a fitted TrendTailBoosting: its trees' form and its ``tail``."""
    from slam_predict.learn.plain import plain_model

    trees = plain_model(regressor.booster_, X_model.shape[1], rng, X_model)
    if trees is None:
        return None
    return dict(trees, tail={"columns": regressor.columns_.tolist(),
                             "slope": regressor.slope_.tolist(),
                             "low": regressor.low_.tolist(), "high": regressor.high_.tolist()})


def plain_pipeline(pipeline, X_check: np.ndarray,
                   rng: np.random.Generator) -> dict[str, Any] | None:
    """The plain form of a fitted robot-model pipeline, or None when a step has none."""
    from slam_predict.learn.plain import plain_model

    steps = dict(pipeline.named_steps)
    log = steps["log"]
    form: dict[str, Any] = {"log_columns": np.asarray(log.columns_, dtype=int).tolist(),
                            "log_floor": np.asarray(log.floor_, dtype=float).tolist(),
                            "scale": None}
    X_model = log.transform(X_check)
    if "scale" in steps:
        scaler = steps["scale"]
        form["scale"] = {"mean": scaler.mean_.tolist(), "scale": scaler.scale_.tolist()}
        X_model = scaler.transform(X_model)
    regressor = steps["model"]
    if type(regressor).__name__ == "GaussianProcessRegressor":
        form["model"] = _gp_form(regressor, X_model.shape[1])
    elif type(regressor).__name__ == "TrendTailBoosting":
        form["model"] = _trend_form(regressor, X_model, rng)
    else:
        form["model"] = plain_model(regressor, X_model.shape[1], rng, X_model)
    return form if form["model"] is not None else None


def probe_rows(X_check: np.ndarray, rng: np.random.Generator, n: int = 64) -> np.ndarray:
    """Check inputs: the rows, jittered copies (± 5 %) and uniform rows over twice their span."""
    X_check = np.asarray(X_check, dtype=float)
    low, high = X_check.min(axis=0), X_check.max(axis=0)
    span = np.where(high > low, high - low, np.abs(high) + 1.0)
    wide = rng.uniform(low - span / 2, high + span / 2, size=(n, X_check.shape[1]))
    jitter = X_check * (1 + 0.05 * rng.normal(size=X_check.shape))
    return np.vstack([X_check, jitter, wide])


def matches(form: dict[str, Any], pipeline, probe: np.ndarray) -> bool:
    """Whether a plain pipeline gives the fitted one's outputs at ``probe`` (to 1e-9)."""
    return bool(np.allclose(evaluate_pipeline(form, probe), pipeline.predict(probe),
                            rtol=TOLERANCE, atol=TOLERANCE))


def plain_component(model, X_check: np.ndarray, seed: int = 0) -> dict[str, Any] | None:
    """The plain form of a fitted ComponentModel (module doc), or None when one of its
    pipelines has no plain form or does not match it on the probe rows."""
    rng = np.random.default_rng(seed)
    probe = probe_rows(X_check, rng)
    forms = []
    for pipeline in [model.estimator, *model.fold_estimators]:
        form = plain_pipeline(pipeline, X_check, rng)
        if form is None or not matches(form, pipeline, probe):
            return None
        forms.append(form)
    return {"component": model.component, "kind": model.kind, "names": list(model.names),
            "offset": float(model.offset), "estimator": forms[0], "fold_estimators": forms[1:],
            "calibration_fold": np.asarray(model.calibration_fold, dtype=int).tolist(),
            "residuals": np.asarray(model.residuals, dtype=float).tolist()}
