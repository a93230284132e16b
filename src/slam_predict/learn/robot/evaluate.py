"""Evaluation of the robot-aware models on POINT truths under three protocols.

- ``buildings`` — leave buildings out: GroupKFold by building (whole buildings per fold);
- ``configs`` — leave robot configurations out: GroupKFold by configuration;
- ``both`` — held-out buildings × held-out configurations: every pair (building fold a,
  configuration fold b) tests the points of a × b with models trained on the rows that share
  neither a building of a nor a configuration of b; each point is tested exactly once.

Folds deal the shuffled groups (seeded) in turn, as :func:`models.group_folds`. With
``repeats`` R > 1 every protocol is run R times on R seeded shufflings of its groups (repeated
grouped K-fold): with 21 buildings one shuffling moves a median error by 2–3 points, so the
scores are the mean (± sd) of the R repeats' scores. Every
model is fitted as it would be shipped (:func:`models.fit_component`, including its
building-grouped CV+ calibration) on the training part only. Scores per protocol, component
and model, on the test POINT values: median percentage error |ŷ − y| / y, R² of the point
values, coverage of the intervals (default 90 %; a std's interval is for the point's own run
count) and the number of test points, each beside the issue's acceptance bars (median error
≤ 20 %, R² ≥ 0.8, coverage ≥ 80 %) with pass/FAIL. Std truths come from 2 runs per point,
themselves uncertain by tens of percent, which bounds the reachable scores of the stds.
"""
from __future__ import annotations

import logging
import math
from collections import defaultdict
from collections.abc import Sequence, Set
from dataclasses import dataclass

import numpy as np

from slam_predict.errors import InputError
from slam_predict.learn.card import PROTOCOLS
from slam_predict.learn.dataset import COMPONENTS, UNITS
from slam_predict.learn.evaluate import percentage_errors, scores
from slam_predict.learn.robot.config import RobotLearningConfig
from slam_predict.learn.robot.models import fit_component, group_folds, is_std
from slam_predict.learn.robot.rundata import RobotTables
from slam_predict.learn.tables import SYMBOLS, err, fmt, markdown

LOG = logging.getLogger(__name__)
BARS = {"median_pct_error": (0.20, "≤"), "r2": (0.8, "≥"), "coverage": (0.8, "≥")}
PROTOCOL_TITLES = {"buildings": "Leave buildings out (GroupKFold by building)",
                   "configs": "Leave robot configurations out (GroupKFold by configuration)",
                   "both": "Held-out buildings × held-out configurations"}


@dataclass
class Split:
    """One train/test division of the POINT rows (indices)."""

    protocol: str
    fold: str
    train: np.ndarray
    test: np.ndarray
    repeat: int = 0


def _fold_rng(seed: int, index: int, which: int, repeat: int) -> np.random.Generator:
    """The shuffling of one protocol's building (0) or configuration (1) groups; repeat 0 is
    the single evaluation's shuffling."""
    key = [seed, index, which] if repeat == 0 else [seed, index, which, repeat]
    return np.random.default_rng(key)


def protocol_splits(tables: RobotTables, protocol: str, n_folds: int,
                    seed: int, repeat: int = 0) -> list[Split]:
    """The splits of one protocol ([] when it has fewer than 2 groups to hold out)."""
    index = PROTOCOLS.index(protocol)
    worlds = group_folds(tables.point_world, n_folds, _fold_rng(seed, index, 0, repeat))
    configs = group_folds(tables.point_config, n_folds, _fold_rng(seed, index, 1, repeat))
    n_worlds, n_configs = len(np.unique(worlds)), len(np.unique(configs))
    if (n_worlds if protocol == "buildings" else n_configs) < 2 or (
            protocol == "both" and n_worlds < 2):
        LOG.warning("protocol %s skipped: fewer than 2 groups to hold out", protocol)
        return []
    if protocol == "buildings":
        cells = [(f"b{a}", worlds == a, worlds != a) for a in range(n_worlds)]
    elif protocol == "configs":
        cells = [(f"c{b}", configs == b, configs != b) for b in range(n_configs)]
    else:
        cells = [(f"b{a}c{b}", (worlds == a) & (configs == b), (worlds != a) & (configs != b))
                 for a in range(n_worlds) for b in range(n_configs)]
    return [Split(protocol, name, np.flatnonzero(train), np.flatnonzero(test), repeat)
            for name, test, train in cells if test.any() and train.any()]


def prediction_rows(tables: RobotTables, split: Split, component: str, kind: str,
                    model, confidence: float) -> list[dict]:
    test = split.test
    y = tables.point_y[component][test]
    runs = tables.point_runs[test]
    keep = np.isfinite(y) & (runs >= 2 if is_std(component) else True)
    test, y, runs = test[keep], y[keep], runs[keep]
    if not len(test):
        return []
    X = tables.point_X[test]
    pred = model.predict(X)
    bounds = (model.interval(X, confidence, runs) if is_std(component)
              else model.interval(X, confidence))
    pct = percentage_errors(y, pred)
    return [{"protocol": split.protocol, "repeat": split.repeat, "fold": split.fold,
             "component": component,
             "model": kind, "world": str(tables.point_world[i]),
             "config": str(tables.point_config[i]), "runs": int(runs[j]), "y": float(y[j]),
             "prediction": float(pred[j]), "low": float(bounds[j, 0]),
             "high": float(bounds[j, 1]), "covered": bool(bounds[j, 0] <= y[j] <= bounds[j, 1]),
             "pct_error": float(pct[j])} for j, i in enumerate(test)]


def evaluate_split(tables: RobotTables, split: Split, config: RobotLearningConfig,
                   components: Sequence[str] = COMPONENTS) -> list[dict]:
    """Prediction rows of every model kind and component on one split's test points."""
    train = tables.subset(split.train)
    rows: list[dict] = []
    for component in components:
        for kind in config.models:
            try:
                model = fit_component(train, component, kind, config)
            except InputError as exc:  # too few rows for the component: the same for every kind
                LOG.warning("%s %s, %s: not fitted (%s)", split.protocol, split.fold,
                            component, exc.one_line())
                break
            rows += prediction_rows(tables, split, component, kind, model, config.confidence)
    return rows


def evaluate(tables: RobotTables, config: RobotLearningConfig,
             protocols: Sequence[str] = PROTOCOLS, components: Sequence[str] = COMPONENTS,
             n_jobs: int = 1) -> list[dict]:
    """Prediction rows of every protocol, split, component and model kind."""
    from joblib import Parallel, delayed

    splits = [s for r in range(config.repeats) for p in protocols
              for s in protocol_splits(tables, p, config.folds, config.seed, r)]
    LOG.info("robot models: %d splits × %d components × %d model kinds", len(splits),
             len(components), len(config.models))
    chunks = Parallel(n_jobs=n_jobs)(delayed(evaluate_split)(tables, s, config, components)
                                     for s in splits)
    return [row for chunk in chunks for row in chunk]


def replicate_r2_ceiling(tables: RobotTables, component: str) -> tuple[float, int]:
    """(R² a perfect model of the true point means would score against the measured point
    means, points used) for a mean component, over the points with 2 or more runs.

    A point mean over n runs misses the true mean by noise of variance σ²/n; with the
    unbiased within-point variance s² for σ², the expected R² of the exact means is
    1 − Σ s²_i/n_i / Σ (ȳ_i − ȳ)². It bounds what any model can score on these truths (the
    acceptance bar of R² ≥ 0.8 is reachable only when this is well above 0.8).
    (NaN, n) with fewer than 3 such points."""
    keep = tables.point_runs >= 2
    n = int(np.count_nonzero(keep))
    if n < 3:
        return math.nan, n
    means = tables.point_y[component][keep]
    stds = tables.point_y[component.replace("_mean", "_std")][keep]   # ddof 1 over the runs
    noise = np.sum(stds ** 2 / tables.point_runs[keep])
    return float(1.0 - noise / np.sum((means - means.mean()) ** 2)), n


def passes(metric: str, value: float) -> bool:
    """True when ``value`` meets the acceptance bar of ``metric`` (NaN fails)."""
    bar, sense = BARS[metric]
    if value is None or math.isnan(value):
        return False
    return value <= bar if sense == "≤" else value >= bar


def _scores(members: Sequence[dict]) -> dict:
    """Test points, median % error, R², coverage and median interval width of some rows."""
    y = np.array([r["y"] for r in members])
    pred = np.array([r["prediction"] for r in members])
    return {"n_points": len(members),
            "median_pct_error": float(np.nanmedian([r["pct_error"] for r in members])),
            "r2": scores(y, pred)["r2"] if len(y) > 1 else math.nan,
            "coverage": float(np.mean([r["covered"] for r in members])),
            "width_median": float(np.median([r["high"] - r["low"] for r in members]))}


def summarize(rows: Sequence[dict]) -> list[dict]:
    """Per (protocol, component, model): n test points, median % error, R², coverage, median
    interval width — each the mean over the repeats, with its sd (``<metric>_sd``, 0 for one
    repeat) — and pass/fail of each bar on the mean."""
    groups: dict[tuple, dict[int, list[dict]]] = defaultdict(lambda: defaultdict(list))
    for row in rows:
        key = (row["protocol"], row["component"], row["model"])
        groups[key][int(row.get("repeat", 0))].append(row)
    out = []
    for (protocol, component, model), repeats in groups.items():
        per_repeat = [_scores(members) for _, members in sorted(repeats.items())]
        entry = {"protocol": protocol, "component": component, "model": model}
        spread = {"repeats": len(per_repeat)}
        for metric in per_repeat[0]:
            values = np.array([s[metric] for s in per_repeat], dtype=float)
            entry[metric] = float(np.mean(values))
            if metric != "n_points":
                spread[f"{metric}_sd"] = float(np.std(values)) if len(values) > 1 else 0.0
        entry["n_points"] = int(round(entry["n_points"]))
        entry.update({f"pass_{m}": passes(m, entry[m]) for m in BARS})
        entry.update(spread)
        out.append(entry)
    out.sort(key=lambda r: (PROTOCOLS.index(r["protocol"]), COMPONENTS.index(r["component"]),
                            r["model"]))
    return out


def summary_from_card(card: dict) -> list[dict]:
    """The summary rows (protocol, component, model and the figures a card keeps) recorded in
    a robot-aware card's ``components``: an evaluation reused by ``learn train
    --evaluation-from``."""
    return [{"protocol": protocol, "component": component, "model": kind, **figures}
            for component, entry in card["components"].items()
            for kind, model in entry["models"].items()
            for protocol, figures in (model.get("metrics") or {}).items()]


def best_models(summary: Sequence[dict], config: RobotLearningConfig,
                excluded: Set[tuple[str, str]] = frozenset()) -> dict[str, str]:
    """Per component the model kind with the lowest median % error under the configured
    protocol (else the first protocol evaluated); ties → higher R²: the robot-aware family's
    rule of "best" (docs/learning.md, "Which model is best"). ``excluded``: (component, kind)
    pairs never chosen (models that fail the monotone check)."""
    have = [p for p in PROTOCOLS if any(r["protocol"] == p for r in summary)]
    if not have:
        return {}
    protocol = config.select_protocol if config.select_protocol in have else have[0]
    best: dict[str, tuple] = {}
    for row in summary:
        if row["protocol"] != protocol or (row["component"], row["model"]) in excluded:
            continue
        r2 = -math.inf if math.isnan(row["r2"]) else row["r2"]
        key = (row["median_pct_error"], -r2, row["model"])
        if row["component"] not in best or key < best[row["component"]]:
            best[row["component"]] = key
    return {c: best[c][2] for c in COMPONENTS if c in best}


def _bar_cell(row: dict, metric: str) -> str:
    return "pass" if row[f"pass_{metric}"] else "**FAIL**"


def _with_sd(row: dict, text: str, sd_text: str) -> str:
    """``text``, followed by ± its sd over the repeats when there are several."""
    return f"{text} ± {sd_text}" if row.get("repeats", 1) > 1 else text


def summary_table(summary: Sequence[dict], protocol: str, best: dict[str, str],
                  confidence: float) -> str:
    """One protocol's Markdown table: figures (mean ± sd over the repeats, if several) and the
    bars' pass/FAIL beside them."""
    rows = []
    for r in (s for s in summary if s["protocol"] == protocol):
        c = r["component"]
        mark = " **(best)**" if best.get(c) == r["model"] else ""
        pct = _with_sd(r, f"{100 * r['median_pct_error']:.1f} %",
                       f"{100 * r.get('median_pct_error_sd', 0.0):.1f}")
        r2 = _with_sd(r, fmt(r["r2"]), fmt(r.get("r2_sd", 0.0)))
        rows.append([SYMBOLS[c], r["model"] + mark, str(r["n_points"]),
                     pct, _bar_cell(r, "median_pct_error"), r2, _bar_cell(r, "r2"),
                     f"{100 * r['coverage']:.1f} %", _bar_cell(r, "coverage"),
                     err(r["width_median"], c)])
    pct = f"{100 * confidence:g} %"
    return markdown(["component", "model", "test points", "median % error", "≤ 20 %", "R²",
                     "≥ 0.8", f"{pct} coverage", "≥ 80 %", "median width"], rows)


def report_markdown(summary: Sequence[dict], best: dict[str, str], header: Sequence[str],
                    confidence: float) -> str:
    """The whole evaluation page (``robots_eval.md``)."""
    parts = ["# Robot-aware models (`own-robots`): evaluation", "", *header, ""]
    for protocol in PROTOCOLS:
        if any(r["protocol"] == protocol for r in summary):
            parts += [f"## {PROTOCOL_TITLES[protocol]}", "",
                      summary_table(summary, protocol, best, confidence)]
        else:
            parts += [f"## {PROTOCOL_TITLES[protocol]}", "",
                      "Not evaluated (fewer than 2 groups to hold out).", ""]
    parts += ["Acceptance bars of issue #18 (stated for mean ε_t, shown for every component): "
              "median percentage error ≤ 20 %, R² ≥ 0.8, interval coverage ≥ 80 %. Units: "
              + ", ".join(f"{SYMBOLS[c]} {UNITS[c]}" for c in COMPONENTS) + "."]
    return "\n".join(parts) + "\n"
