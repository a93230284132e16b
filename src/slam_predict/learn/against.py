"""Leave-one-building-out predictions scored against another study's measurements.

A model trained on our own campaigns is only as good as its predictions of what a real
collection chain measures. :func:`leave_one_out_against` predicts every building of a dataset
that the other table also holds, each with the model refitted on the other buildings of the
dataset (the model kind of a shipped card, its learning configuration), and scores the
prediction against the other table's value for that building (e.g. the seed study's measured
mean ε_t), not against our own measurement. Scores: the median percentage error
|ŷ − y| / y and the coverage of the 90 % intervals.
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from slam_predict.config import from_dict
from slam_predict.errors import InputError
from slam_predict.learn.config import LearningConfig
from slam_predict.learn.dataset import Dataset
from slam_predict.learn.evaluate import loo_one

BAR_MEDIAN_PCT_ERROR = 0.12   # the acceptance bar of the own models against the seed study
# leaving one building out keeps n - 1; the interval's CV+ then fits each fold on n - 2, and a
# fit needs 2 buildings
MIN_BUILDINGS = 4


def card_models(card: Mapping[str, Any], components: Sequence[str]) -> dict[str, str]:
    """Component → the model id the card shipped (its ``best``); InputError when absent."""
    chosen = {}
    for component in components:
        best = card.get("components", {}).get(component, {}).get("best")
        if not best:
            raise InputError(f"model card '{card.get('name', '?')}' has no {component} model")
        chosen[component] = str(best)
    return chosen


def card_learning_config(card: Mapping[str, Any]) -> LearningConfig:
    """The learning configuration a plan-only card was trained with."""
    if "learning_config" not in card:
        raise InputError(f"model card '{card.get('name', '?')}' records no learning "
                         "configuration (not a plan-only model)")
    return from_dict(LearningConfig, dict(card["learning_config"]), "model card")


def leave_one_out_against(data: Dataset, config: LearningConfig, chosen: Mapping[str, str],
                          truth: Mapping[str, Mapping[str, float]],
                          source: str = "dataset") -> list[dict]:
    """Per component of ``chosen`` and per building of ``data`` found in ``truth``: the
    leave-one-building-out prediction (model refitted without the building), our own value,
    the other table's value and the percentage error against it. InputError naming ``source``
    when ``data`` holds fewer than :data:`MIN_BUILDINGS` buildings."""
    if len(data.worlds) < MIN_BUILDINGS:
        raise InputError(f"{source}: {len(data.worlds)} building(s); leaving one out needs "
                         f"at least {MIN_BUILDINGS}")
    rows = []
    for component, model_id in chosen.items():
        for i, world in enumerate(data.worlds):
            if world not in truth:
                continue
            row = loo_one(data, config, component, model_id, i)
            rows.append(scored_against(row, float(truth[world][component])))
    return rows


def scored_against(row: Mapping[str, Any], theirs: float) -> dict:
    """A prediction row (``y`` our measurement, ``prediction``, ``low``, ``high``) scored
    against the other table's value ``theirs``: ``ours`` keeps our measurement, ``y`` becomes
    theirs, with the interval's ``covered`` and the ``pct_error`` against it."""
    return {**row, "ours": row["y"], "y": theirs,
            "covered": bool(row["low"] <= theirs <= row["high"]),
            "pct_error": abs(row["prediction"] - theirs) / theirs}


def summary(rows: Sequence[dict]) -> list[dict]:
    """Per (component, model): buildings, median % error against the other table, interval
    coverage, and the median % error of our own measurement against it (the chain's part)."""
    out = []
    for key in dict.fromkeys((r["component"], r["model"]) for r in rows):
        group = [r for r in rows if (r["component"], r["model"]) == key]
        chain = [abs(r["ours"] - r["y"]) / r["y"] for r in group]
        out.append({"component": key[0], "model": key[1], "n_buildings": len(group),
                    "median_pct_error": float(np.median([r["pct_error"] for r in group])),
                    "coverage": float(np.mean([r["covered"] for r in group])),
                    "chain_median_pct_error": float(np.median(chain))})
    return out


def markdown(rows: Sequence[dict], model_name: str, truth_name: str) -> str:
    """The per-building table and the summary lines, as markdown."""
    lines = [f"## Leave-one-building-out predictions of {model_name} against {truth_name}", "",
             "| building | component | model | ours measured | predicted (90 % interval) | "
             "theirs | error |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['world']} | {r['component']} | {r['model']} | {r['ours']:.4g} | "
                     f"{r['prediction']:.4g} ({r['low']:.4g}–{r['high']:.4g}) | {r['y']:.4g} | "
                     f"{100 * r['pct_error']:.0f} % |")
    lines.append("")
    for s in summary(rows):
        verdict = ("pass" if s["median_pct_error"] <= BAR_MEDIAN_PCT_ERROR else "FAIL")
        bar = f" (bar ≤ {100 * BAR_MEDIAN_PCT_ERROR:.0f} %: {verdict})" \
            if s["component"] == "trans_mean" else ""
        lines.append(f"- {s['component']} ({s['model']}, {s['n_buildings']} buildings): median "
                     f"error {100 * s['median_pct_error']:.1f} %{bar}; interval coverage "
                     f"{100 * s['coverage']:.0f} %; our own measurement's median error "
                     f"{100 * s['chain_median_pct_error']:.1f} %")
    return "\n".join(lines) + "\n"
