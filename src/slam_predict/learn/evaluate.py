"""Evaluation protocol: repeated seeded 80/20 splits and leave-one-building-out.

For every split seed s (``first_seed`` … ``first_seed + n_splits − 1``) the buildings are
permuted by ``numpy.random.default_rng(s)``; the first round(test_fraction · n) are the test set.
Every model is fitted on the rest and scored on the test set: R², RMSE (m or rad) and
NRMSE = RMSE / (y_max − y_min) of the test set, NRMSE_all = RMSE / (y_max − y_min) of all
buildings (what the thesis' printed NRMSE values correspond to: 0.145 m / 7.92 % ≈ the range of
its whole dataset), plus the percentage error |ŷ − y| / y of each test building. The best
model per component is the one with the highest mean test R² (reference models excluded).
Leave-one-building-out fits the conformal-wrapped models on all other buildings and checks
whether the held-out building's value lies in its interval.
"""
from __future__ import annotations

import logging
import math
from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from joblib import Parallel, delayed
from sklearn.base import clone

from slam_predict.learn.config import LearningConfig
from slam_predict.learn.dataset import COMPONENTS, Dataset
from slam_predict.learn.models import (
    SINGLE,
    conformal,
    describe,
    design,
    is_reference,
    model_ids,
    used_features,
)

LOG = logging.getLogger(__name__)


def random_splits(n: int, n_splits: int, test_fraction: float,
                  first_seed: int = 0) -> list[tuple[int, np.ndarray, np.ndarray]]:
    """[(seed, train rows, test rows)]: seeded permutations, test = first round(f·n) rows."""
    n_test = min(n - 2, max(2, int(round(test_fraction * n))))
    if n_test < 2:
        raise ValueError(f"{n} buildings are too few for train/test splits")
    splits = []
    for seed in range(first_seed, first_seed + n_splits):
        order = np.random.default_rng(seed).permutation(n)
        splits.append((seed, np.sort(order[n_test:]), np.sort(order[:n_test])))
    return splits


def scores(y_true: np.ndarray, y_pred: np.ndarray) -> dict[str, float]:
    """R², RMSE and NRMSE = RMSE / (max − min of y_true)."""
    residual = y_true - y_pred
    rmse = float(np.sqrt(np.mean(residual ** 2)))
    total = float(np.sum((y_true - y_true.mean()) ** 2))
    r2 = 1.0 - float(np.sum(residual ** 2)) / total if total > 0 else math.nan
    spread = float(y_true.max() - y_true.min())
    return {"r2": r2, "rmse": rmse, "nrmse": rmse / spread if spread > 0 else math.nan}


def percentage_errors(y_true: np.ndarray, y_pred: np.ndarray) -> np.ndarray:
    """|ŷ − y| / y per building (NaN where y ≤ 0)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(y_true > 0, np.abs(y_pred - y_true) / y_true, np.nan)


@dataclass
class SplitResult:
    """One model's test scores on one split for one component."""

    model: str
    component: str
    seed: int
    r2: float
    rmse: float
    nrmse: float
    nrmse_all: float
    pct_error: float
    info: dict = field(default_factory=dict)
    features: list[str] = field(default_factory=list)


def _one_split(data: Dataset, config: LearningConfig, ids: Sequence[str],
               components: Sequence[str], seed: int, train, test) -> list[SplitResult]:
    out = []
    for component in components:
        y = data.target(component)
        spread = float(y.max() - y.min())
        for model_id in ids:
            spec = design(model_id, data, config)
            model = clone(spec.estimator).fit(spec.X[train], y[train])
            pred = model.predict(spec.X[test])
            s = scores(y[test], pred)
            pct = float(np.nanmean(percentage_errors(y[test], pred)))
            out.append(SplitResult(model_id, component, seed, s["r2"], s["rmse"], s["nrmse"],
                                   s["rmse"] / spread if spread > 0 else math.nan, pct,
                                   describe(model), used_features(model, spec.feature_names)))
    return out


def evaluate_splits(data: Dataset, config: LearningConfig,
                    components: Sequence[str] = COMPONENTS, ids: Sequence[str] | None = None,
                    n_jobs: int = 1) -> list[SplitResult]:
    """Scores of every model on every split and component."""
    ev = config.evaluation
    ids = list(ids) if ids is not None else model_ids(config, data)
    splits = random_splits(len(data), ev.n_splits, ev.test_fraction, ev.first_seed)
    LOG.info("evaluating %d models x %d components on %d splits of %d buildings", len(ids),
             len(components), len(splits), len(data))
    jobs = (delayed(_one_split)(data, config, ids, components, seed, train, test)
            for seed, train, test in splits)
    return [r for chunk in Parallel(n_jobs=n_jobs)(jobs) for r in chunk]


def summarize(results: Sequence[SplitResult]) -> list[dict]:
    """Per (model, component): mean/std of R², mean RMSE, NRMSE, percentage error, choices."""
    groups: dict[tuple[str, str], list[SplitResult]] = defaultdict(list)
    for r in results:
        groups[(r.model, r.component)].append(r)
    rows = []
    for (model, component), group in groups.items():
        r2 = np.array([g.r2 for g in group])
        row = {"model": model, "component": component, "n_splits": len(group),
               "r2_mean": float(np.nanmean(r2)), "r2_std": float(np.nanstd(r2)),
               "r2_median": float(np.nanmedian(r2)),
               "rmse_mean": float(np.mean([g.rmse for g in group])),
               "nrmse_mean": float(np.nanmean([g.nrmse for g in group])),
               "nrmse_all_mean": float(np.nanmean([g.nrmse_all for g in group])),
               "pct_error_mean": float(np.nanmean([g.pct_error for g in group])),
               "n_features_mean": float(np.mean([g.info.get("n_features", 1) for g in group]))}
        row.update(_choices(group))
        rows.append(row)
    rows.sort(key=lambda r: (COMPONENTS.index(r["component"]), -_sortable(r["r2_mean"])))
    return rows


def _sortable(value: float) -> float:
    return -math.inf if math.isnan(value) else value


def _choices(group: Sequence[SplitResult]) -> dict:
    """Most frequent hyperparameters and features chosen across splits."""
    out: dict = {}
    for key in ("k", "alpha", "l1_ratio"):
        values = [g.info[key] for g in group if key in g.info]
        if values:
            uniq, counts = np.unique(values, return_counts=True)
            out[f"{key}_mode"] = float(uniq[np.argmax(counts)])
    counts: dict[str, int] = defaultdict(int)
    for g in group:
        for name in g.features:
            counts[name] += 1
    if counts and not group[0].model.startswith(SINGLE):
        top = sorted(counts.items(), key=lambda kv: (-kv[1], kv[0]))[:10]
        out["top_features"] = ";".join(f"{name}({n})" for name, n in top)
    return out


def best_models(summary: Sequence[dict], single_only: bool = False) -> dict[str, str]:
    """Component → model id with the highest mean test R² (reference models excluded): the
    plan-only family's rule of "best" (docs/learning.md, "Which model is best").

    Only models with a mean test R² > 0 compete: a model no better than the training mean is
    never the best, so a component where none beats it has no entry.
    """
    best: dict[str, tuple[float, str]] = {}
    for row in summary:
        model = row["model"]
        if is_reference(model) or (single_only and not model.startswith(SINGLE)):
            continue
        if not row["r2_mean"] > 0:
            continue
        key = (_sortable(row["r2_mean"]), model)
        if row["component"] not in best or key[0] > best[row["component"]][0]:
            best[row["component"]] = key
    return {c: m for c, (_, m) in best.items()}


def ranked(summary: Sequence[dict], component: str, prefix: str = "") -> list[dict]:
    """Rows of ``component`` whose model starts with ``prefix``, best mean R² first."""
    rows = [r for r in summary if r["component"] == component and r["model"].startswith(prefix)]
    return sorted(rows, key=lambda r: -_sortable(r["r2_mean"]))


def loo_one(data: Dataset, config: LearningConfig, component: str, model_id: str,
            i: int) -> dict:
    """Building ``i`` predicted (value and conformal interval) by ``model_id`` fitted on the
    other buildings, beside its measured value ``y`` and the percentage error."""
    y = data.target(component)
    spec = design(model_id, data, config)
    train = np.delete(np.arange(len(data)), i)
    model = conformal(spec.estimator, config).fit(spec.X[train], y[train])
    value = float(model.predict(spec.X[i:i + 1])[0])
    low, high = (float(v) for v in model.predict_interval(spec.X[i:i + 1])[0])
    return {"world": data.worlds[i], "component": component, "model": model_id,
            "y": float(y[i]), "prediction": value, "low": low, "high": high,
            "covered": bool(low <= y[i] <= high),
            "pct_error": float(percentage_errors(y[i:i + 1], np.array([value]))[0])}


def leave_one_out(data: Dataset, config: LearningConfig, chosen: dict[str, Sequence[str]],
                  n_jobs: int = 1) -> list[dict]:
    """Leave-one-building-out predictions with conformal intervals for the chosen models."""
    jobs = [delayed(loo_one)(data, config, component, model_id, i)
            for component, ids in chosen.items() for model_id in ids for i in range(len(data))]
    LOG.info("leave-one-building-out: %d fits of conformal models", len(jobs))
    return list(Parallel(n_jobs=n_jobs)(jobs))


def coverage(loo_rows: Sequence[dict]) -> list[dict]:
    """Per (component, model): interval coverage, mean width, prediction R², pct error."""
    groups: dict[tuple[str, str], list[dict]] = defaultdict(list)
    for row in loo_rows:
        groups[(row["component"], row["model"])].append(row)
    out = []
    for (component, model), rows in groups.items():
        y = np.array([r["y"] for r in rows])
        pred = np.array([r["prediction"] for r in rows])
        out.append({"component": component, "model": model, "n_buildings": len(rows),
                    "coverage": float(np.mean([r["covered"] for r in rows])),
                    "width_mean": float(np.mean([r["high"] - r["low"] for r in rows])),
                    "r2": scores(y, pred)["r2"], "rmse": scores(y, pred)["rmse"],
                    "pct_error_mean": float(np.nanmean([r["pct_error"] for r in rows])),
                    "pct_error_median": float(np.nanmedian([r["pct_error"] for r in rows]))})
    out.sort(key=lambda r: (COMPONENTS.index(r["component"]), r["model"]))
    return out


def loo_choice(summary: Sequence[dict], config: LearningConfig) -> dict[str, list[str]]:
    """Models to check with leave-one-building-out, per component."""
    best = best_models(summary)
    best_single = best_models(summary, single_only=True)
    chosen: dict[str, list[str]] = {}
    for component in best:
        ids = [best[component]]
        if best_single.get(component) and best_single[component] not in ids:
            ids.append(best_single[component])
        if config.evaluation.loo_models == "all":
            ids += [m for m in config.models if m != "single" and m not in ids]
        chosen[component] = ids
    return chosen
