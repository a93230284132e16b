"""Result tables in the style of the thesis' Tables 7.1–7.5, as Markdown and CSV."""
from __future__ import annotations

import csv
import io
import math
from collections.abc import Sequence

from slam_predict.learn.dataset import COMPONENTS, UNITS
from slam_predict.learn.evaluate import SplitResult, best_models, ranked
from slam_predict.learn.models import REFERENCE, SINGLE, is_reference

SCORES = ["R² (mean ± std)", "RMSE", "NRMSE (test range)", "NRMSE (all)"]
SYMBOLS = {"trans_mean": "mean ε_t", "trans_std": "std ε_t", "rot_mean": "mean ε_r",
           "rot_std": "std ε_r"}


def markdown(header: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    """A GitHub Markdown table."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def csv_text(rows: Sequence[dict]) -> str:
    """CSV of dict rows (the union of their keys, in first-seen order)."""
    keys: list[str] = []
    for row in rows:
        keys += [k for k in row if k not in keys]
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=keys, lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: _csv_value(v) for k, v in row.items()})
    return out.getvalue()


def _csv_value(value):
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, (list, tuple)):
        return ";".join(str(v) for v in value)
    return value


def fmt(value: float, digits: int = 3) -> str:
    """A number with ``digits`` decimals; '–' for NaN."""
    return "–" if value is None or (isinstance(value, float) and math.isnan(value)) \
        else f"{value:.{digits}f}"


def err(value: float, component: str) -> str:
    """An RMSE with its unit (m: 3 decimals, rad: 4)."""
    return f"{fmt(value, 3 if UNITS[component] == 'm' else 4)} {UNITS[component]}"


def pct(value: float) -> str:
    """A fraction as a percentage."""
    return "–" if math.isnan(value) else f"{100 * value:.2f} %"


def model_label(model: str) -> str:
    """Readable model name: the feature for single-feature models."""
    if model.startswith(SINGLE):
        return f"line on {model[len(SINGLE):]}"
    if model.startswith(REFERENCE):
        return f"line on table column {model[len(REFERENCE):]}"
    return model


def _score_cells(row: dict) -> list[str]:
    c = row["component"]
    return [f"{fmt(row['r2_mean'])} ± {fmt(row['r2_std'])}", err(row["rmse_mean"], c),
            pct(row["nrmse_mean"]), pct(row["nrmse_all_mean"])]


def single_feature_table(summary: Sequence[dict], rank: int = 0) -> str:
    """Like Tables 7.1 (rank 0) / 7.2 (rank 1): the rank-th best single feature per component."""
    rows = []
    for c in COMPONENTS:
        options = ranked(summary, c, SINGLE)
        if len(options) > rank:
            row = options[rank]
            rows.append([SYMBOLS[c], row["model"][len(SINGLE):], *_score_cells(row)])
    return markdown(["component", "feature", *SCORES], rows)


def reference_table(summary: Sequence[dict]) -> str:
    """Single-feature lines on the source table's own columns (yardsticks, like Table 7.3)."""
    rows = [[SYMBOLS[r["component"]], r["model"][len(REFERENCE):], *_score_cells(r)]
            for c in COMPONENTS for r in ranked(summary, c, REFERENCE)]
    return markdown(["component", "table column", *SCORES], rows)


def models_table(summary: Sequence[dict]) -> str:
    """Every multi-feature model plus the best single feature, per component."""
    best = best_models(summary)
    rows = []
    for c in COMPONENTS:
        best_single = next(iter(ranked(summary, c, SINGLE)), None)
        for r in ranked(summary, c):
            if is_reference(r["model"]) or (r["model"].startswith(SINGLE) and r is not best_single):
                continue
            mark = " **(best)**" if best.get(c) == r["model"] else ""
            rows.append([SYMBOLS[c], model_label(r["model"]) + mark, *_score_cells(r),
                         fmt(r["r2_median"]), pct(r["pct_error_mean"]),
                         fmt(r["n_features_mean"], 1)])
    return markdown(["component", "model", *SCORES, "median R²", "mean rel. error",
                     "features used"], rows)


def per_split_table(results: Sequence[SplitResult], model: str, seeds: Sequence[int]) -> str:
    """Like Tables 7.4/7.5: a model's choices and scores on single splits."""
    rows = []
    for seed in seeds:
        for r in results:
            if r.model == model and r.seed == seed:
                rows.append([str(seed), SYMBOLS[r.component], str(r.info.get("n_features", "")),
                             _choice(r.info), fmt(r.r2), err(r.rmse, r.component), pct(r.nrmse),
                             pct(r.nrmse_all)])
    return markdown(["split seed", "component", "n. features", "chosen", "R²", "RMSE",
                     "NRMSE (test range)", "NRMSE (all)"], rows)


def _choice(info: dict) -> str:
    if "alpha" in info:
        return f"alpha {info['alpha']:g}, l1_ratio {info['l1_ratio']:g}"
    if "k" in info:
        return f"K = {info['k']}"
    return ""


def coverage_table(rows: Sequence[dict], confidence: float) -> str:
    """Leave-one-building-out: interval coverage, width, R², percentage error."""
    out = []
    for r in rows:
        c = r["component"]
        out.append([SYMBOLS[c], model_label(r["model"]), f"{100 * r['coverage']:.1f} %",
                    err(r["width_mean"], c), fmt(r["r2"]), err(r["rmse"], c),
                    pct(r["pct_error_mean"]), pct(r["pct_error_median"])])
    return markdown(["component", "model", f"{100 * confidence:g} % interval coverage",
                     "mean width", "R²", "RMSE", "mean rel. error", "median rel. error"], out)


def best_table(summary: Sequence[dict]) -> str:
    """The chosen model per component."""
    best = best_models(summary)
    by_key: dict[tuple, dict] = {(r["model"], r["component"]): r for r in summary}
    rows = [[SYMBOLS[c], model_label(best[c]), *_score_cells(by_key[(best[c], c)])]
            if c in best else [SYMBOLS[c], "none (no model with R² > 0)", *[""] * len(SCORES)]
            for c in COMPONENTS if c in best or any(r["component"] == c for r in summary)]
    return markdown(["component", "best model", *SCORES], rows)
