"""Plan features → the four error components with conformal intervals (plan-only models).

:func:`predict_features` evaluates each component's best model on a feature vector computed
with the card's feature configuration (:func:`slam_predict.features.plan.plan_features`;
:func:`component_entry`):

- the interval always contains the prediction (CV+ bounds come from the fold models, the
  value from the model fitted on every building, so the value can fall outside them: the
  interval is widened to it);
- a model output ≤ 0 is not an error statistic: the component is reported as ``below_range``
  ("below the model's range") with its raw output, never as 0 m;
- a component whose best model does not beat the training mean (evaluation R² ≤ 0,
  :func:`slam_predict.learn.store.skilful`) is reported as ``no_model``.

Features outside the training range are reported as warnings.
"""
from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from slam_predict.errors import InputError, did_you_mean
from slam_predict.learn.card import training_fitted_settings
from slam_predict.learn.dataset import COMPONENTS, UNITS
from slam_predict.learn.plain import predict_plain
from slam_predict.learn.store import ModelStore, evaluation_r2

LOG = logging.getLogger(__name__)


def components_of(component: str) -> Sequence[str]:
    """``all`` → the four components; one name → itself; InputError otherwise."""
    if component == "all":
        return COMPONENTS
    if component not in COMPONENTS:
        choices = ("all",) + COMPONENTS
        raise InputError(f"unknown component '{component}' (choose from "
                         f"{', '.join(choices)})" + did_you_mean(component, choices))
    return (component,)


def range_warning(features: dict[str, float], used: Sequence[str],
                  ranges: dict[str, list[float]], shown: int = 6) -> str | None:
    """One warning naming the used features outside their training range (None if none)."""
    outside = []
    for name in used:
        low, high = ranges.get(name, (-math.inf, math.inf))
        if not low <= features[name] <= high:
            outside.append(f"{name} = {features[name]:.4g} not in [{low:.4g}, {high:.4g}]")
    if not outside:
        return None
    more = f" (and {len(outside) - shown} more)" if len(outside) > shown else ""
    return ("the prediction extrapolates: features outside the training range: "
            + "; ".join(outside[:shown]) + more)


def _evaluate(store: ModelStore, component: str, model_id: str, x: np.ndarray):
    """(value, low, high): from the model's plain form if any, else the pickled model."""
    form = store.plain(component, model_id)
    if form is not None:
        return tuple(float(v) for v in predict_plain(form, x)[0])
    estimator = store.estimator(component, model_id)
    low, high = estimator.predict_interval(x)[0]
    return float(estimator.predict(x)[0]), float(low), float(high)


def component_entry(value: float, low: float, high: float, unit: str,
                    model: str) -> dict[str, Any]:
    """The reported form of one component's raw model output ``value`` and interval.

    ``status`` is ``ok`` (value > 0, 0 ≤ low ≤ value ≤ high, low < high) or ``below_range``
    (value ≤ 0: ``value`` and ``low`` are None, ``high`` the interval's upper bound when it is
    > 0, else None). ``raw_value``/``raw_low``/``raw_high`` keep the model's own numbers.
    """
    entry: dict[str, Any] = {"status": "ok", "value": value, "low": min(low, value),
                             "high": max(high, value), "model": model, "unit": unit,
                             "raw_value": value, "raw_low": low, "raw_high": high}
    if value <= 0:
        top = entry["high"]
        entry.update(status="below_range", value=None, low=None,
                     high=top if top > 0 else None)
    else:
        entry["low"] = max(entry["low"], 0.0)
        if not entry["high"] > entry["low"]:  # zero-width: no usable interval
            entry.update(low=None, high=None)
    return entry


def no_model_entry(store: ModelStore, component: str) -> dict[str, Any]:
    """The reported form of a component without a model that beats the training mean."""
    comp = store.card["components"].get(component) or {}
    model_id = comp.get("best")
    r2 = evaluation_r2(comp.get("models", {}).get(model_id, {}).get("metrics", {}))
    return {"status": "no_model", "value": None, "low": None, "high": None,
            "model": f"{store.name}/{model_id}" if model_id else None,
            "unit": UNITS[component], "r2": min(r2) if r2 else None}


def describe_entry(component: str, entry: dict[str, Any]) -> str | None:
    """A warning for a component that has no plain value (None when it has one)."""
    unit = UNITS[component]
    if entry["status"] == "below_range":
        bound = (f"; upper bound of its interval {entry['high']:.4g} {unit}"
                 if entry["high"] is not None else "")
        return (f"{component}: the model's output {entry['raw_value']:.4g} {unit} is below "
                f"the model's range (an error statistic cannot be ≤ 0): the plan lies "
                f"outside what the model learnt{bound}")
    if entry["status"] == "no_model":
        r2 = f" (best evaluation R² {entry['r2']:.3g})" if entry["r2"] is not None else ""
        return (f"{component}: no model of this store predicts it better than the training "
                f"mean{r2}")
    if entry["low"] is None:
        return f"{component}: the model gives no interval (its calibration residuals are 0)"
    return None


def predict_features(features: dict[str, float], store: ModelStore,
                     component: str = "all") -> dict[str, Any]:
    """Predictions of ``store`` for one feature vector (name → value)."""
    card = store.card
    names = list(card["features"])
    missing = [n for n in names if n not in features]
    if missing:
        raise InputError(f"feature '{missing[0]}' needed by model {store.name} was not computed")
    x = np.array([[float(features[n]) for n in names]])
    result: dict[str, Any] = {"model_store": store.name, "setting": card["setting"],
                              "confidence": card.get("confidence", 0.9),
                              "fitted_settings": training_fitted_settings(card)}
    warnings_: list[str] = list(store.notes)
    used_all: list[str] = []
    for comp in components_of(component):
        model_id = store.offered(comp)
        if model_id is None:
            result[comp] = no_model_entry(store, comp)
        else:
            used = card["components"][comp]["models"][model_id]["features_used"]
            bad = [n for n in used if not math.isfinite(float(features[n]))]
            if bad:
                raise InputError(f"feature '{bad[0]}' could not be computed for this plan")
            result[comp] = component_entry(*_evaluate(store, comp, model_id, x),
                                           unit=UNITS[comp], model=f"{store.name}/{model_id}")
            used_all += [n for n in used if n not in used_all]
        note = describe_entry(comp, result[comp])
        warnings_ += [note] if note else []
    note = range_warning(features, used_all, card.get("feature_ranges", {}))
    result["warnings"] = warnings_ + ([note] if note else [])
    return result


def check_feature_version(store: ModelStore, retrain: str = "slam-predict learn train") -> None:
    """InputError unless this installation computes the card's feature version (the message
    names the ``retrain`` command)."""
    from slam_predict.features.plan import version_of

    current = version_of(store.card.get("feature_config") or {})
    if current != store.card["feature_version"]:
        raise InputError(f"model uses feature version {store.card['feature_version']}, this "
                         f"slam_predict computes {current}; retrain with '{retrain}'",
                         store.path / "card.json")
