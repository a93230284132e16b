"""Run the whole evaluation protocol and write its folder (CSV, Markdown tables, figures).

Folder contents: ``splits.csv`` (every model × component × split), ``summary.csv`` (means over
splits), ``loo.csv`` / ``coverage.csv`` (leave-one-building-out predictions and interval
coverage), ``best.json``, ``tables.md`` and ``regression.png`` (like the thesis' Figure 7.2; plus
``regression_reference.png`` on the table's own columns when the dataset has them).
"""
from __future__ import annotations

import json
import os
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from slam_predict.atomic import atomic_dir
from slam_predict.config import to_dict
from slam_predict.learn import tables
from slam_predict.learn.config import LearningConfig
from slam_predict.learn.dataset import COMPONENTS, Dataset
from slam_predict.learn.evaluate import (
    SplitResult,
    best_models,
    coverage,
    evaluate_splits,
    leave_one_out,
    loo_choice,
    summarize,
)
from slam_predict.learn.models import SINGLE
from slam_predict.learn.plots import regression_figure


@dataclass
class Outcome:
    """Everything the evaluation produced."""

    results: list[SplitResult]
    summary: list[dict]
    best: dict[str, str]
    best_single: dict[str, str]
    loo: list[dict]
    coverage: list[dict]


def run_evaluation(data: Dataset, config: LearningConfig,
                   components: Sequence[str] = COMPONENTS, n_jobs: int = 1) -> Outcome:
    """Repeated splits, then (if configured) leave-one-building-out on the chosen models."""
    results = evaluate_splits(data, config, components, n_jobs=n_jobs)
    summary = summarize(results)
    loo_rows: list[dict] = []
    if config.evaluation.leave_one_out:
        loo_rows = leave_one_out(data, config, loo_choice(summary, config), n_jobs=n_jobs)
    return Outcome(results, summary, best_models(summary),
                   best_models(summary, single_only=True), loo_rows, coverage(loo_rows))


def _header(data: Dataset, config: LearningConfig, title: str) -> str:
    ev = config.evaluation
    runs = data.runs[np.isfinite(data.runs)]
    lines = [f"# {title}", "",
             f"- buildings: {len(data)}; features: {len(data.feature_names)} "
             f"(version {', '.join(sorted(set(data.feature_version)))})",
             f"- setting: {', '.join(sorted(set(data.setting)))}; SLAM config: "
             f"{', '.join(sorted(set(data.slam_config_hash)))}; runs per building: "
             + (f"{runs.min():g}–{runs.max():g}" if len(runs) else "unknown"),
             f"- protocol: {ev.n_splits} random {100 * (1 - ev.test_fraction):g}/"
             f"{100 * ev.test_fraction:g} splits, seeds {ev.first_seed}–"
             f"{ev.first_seed + ev.n_splits - 1}; scores on the test buildings; NRMSE = RMSE / "
             "(max − min of the test targets), NRMSE (all) = RMSE / (max − min over all "
             "buildings), as the thesis' tables; best model = highest mean R².", ""]
    return "\n".join(lines)


def tables_markdown(data: Dataset, config: LearningConfig, outcome: Outcome, title: str) -> str:
    """The Markdown results page."""
    seeds = [config.evaluation.first_seed, config.evaluation.first_seed + 1]
    parts = [_header(data, config, title),
             "## Best model per component\n", tables.best_table(outcome.summary),
             "\n## Best single feature (like Table 7.1)\n",
             tables.single_feature_table(outcome.summary, 0),
             "\n## Second-best single feature (like Table 7.2)\n",
             tables.single_feature_table(outcome.summary, 1)]
    if data.reference:
        parts += ["\n## Lines on the source table's own columns (yardsticks, not features)\n",
                  tables.reference_table(outcome.summary)]
    parts += ["\n## All models\n", tables.models_table(outcome.summary)]
    for model, label in (("elasticnet", "ElasticNet (like Tables 7.4–7.5)"),
                         ("fregression", "F-regression voting")):
        if any(r.model == model for r in outcome.results):
            parts += [f"\n## {label}, first two splits\n",
                      tables.per_split_table(outcome.results, model, seeds)]
    if outcome.coverage:
        parts += ["\n## Leave-one-building-out\n",
                  tables.coverage_table(outcome.coverage, config.conformal.confidence)]
    parts += ["\n![regression lines](regression.png)\n"]
    return "\n".join(parts)


def write_evaluation(data: Dataset, config: LearningConfig, outcome: Outcome,
                     out_dir: os.PathLike | str, title: str = "Evaluation") -> Path:
    """Write the evaluation folder atomically; returns its path."""
    out_dir = Path(out_dir)
    with atomic_dir(out_dir) as tmp:
        (tmp / "splits.csv").write_text(tables.csv_text([_flat(r) for r in outcome.results]))
        (tmp / "summary.csv").write_text(tables.csv_text(outcome.summary))
        if outcome.loo:
            (tmp / "loo.csv").write_text(tables.csv_text(outcome.loo))
            (tmp / "coverage.csv").write_text(tables.csv_text(outcome.coverage))
        best = {"best": outcome.best, "best_single": outcome.best_single,
                "config": to_dict(config), "buildings": list(data.worlds)}
        (tmp / "best.json").write_text(json.dumps(best, indent=2) + "\n")
        (tmp / "tables.md").write_text(tables_markdown(data, config, outcome, title))
        single = {c: m[len(SINGLE):] for c, m in outcome.best_single.items()}
        if single:
            regression_figure(data, single, tmp / "regression.png",
                              f"{title}: best single feature per component")
        if data.reference:
            column = ("ref_voronoi_distance" if "ref_voronoi_distance" in data.reference
                      else sorted(data.reference)[0])
            regression_figure(data, {c: column for c in COMPONENTS},
                              tmp / "regression_reference.png", f"{title}: table column")
    return out_dir


def _flat(result: SplitResult) -> dict:
    row = asdict(result)
    info = row.pop("info")
    row.update(info)
    row["features"] = ";".join(result.features)
    return row
