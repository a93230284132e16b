"""Predictions of the given models for the campaign's worlds, next to the measured values.

The world of a campaign is found from its run records' ``world_file`` (as written, relative to
the current folder, to the campaign folder or its parents), else as ``<world>.world`` in the
package's ``worlds/`` folder. Features are computed once per world and feature configuration
(:func:`slam_predict.features.plan.compute`), then each model's best estimator per
component predicts (:meth:`slam_predict.learn.model.PlanModel.predict`). A world that cannot
be found or featurised is a note on the page.
"""
from __future__ import annotations

import json
import logging
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from slam_predict.errors import InputError
from slam_predict.paths import PROJECT_ROOT
from slam_predict.report import html as H
from slam_predict.report.campaign import Campaign
from slam_predict.report.models import COMPONENTS, LABELS, UNITS, ModelEntry
from slam_predict.report.sections import robot_text

LOG = logging.getLogger(__name__)
SHIPPED_WORLDS = PROJECT_ROOT / "worlds"


@dataclass
class Prediction:
    """One world × component: measured (campaign mean over runs) and predicted values."""

    world: str
    component: str
    runs: int
    measured: float
    value: float
    low: float
    high: float
    status: str = "ok"
    raw_value: float = math.nan

    @classmethod
    def of(cls, world: str, component: str, runs: int, measured: float, entry: dict):
        """From a component entry of :func:`predict_features` (None → NaN)."""
        def num(key):
            value = entry.get(key)
            return math.nan if value is None else float(value)

        low = 0.0 if entry["status"] == "below_range" else num("low")
        return cls(world, component, runs, measured, num("value"), low, num("high"),
                   entry["status"], num("raw_value"))

    @property
    def has_interval(self) -> bool:
        return math.isfinite(self.low) and math.isfinite(self.high)

    @property
    def inside(self) -> bool:
        return self.has_interval and self.low <= self.measured <= self.high

    @property
    def relative_error(self) -> float:
        """(predicted − measured) / measured, NaN when measured is 0."""
        return (self.value - self.measured) / self.measured if self.measured else math.nan


@dataclass
class ModelPredictions:
    """All predictions of one model store and the warnings/notes they produced."""

    items: list[Prediction] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)


def find_world_file(campaign: Campaign, name: str,
                    worlds_dir: Path | None = None) -> Path | None:
    """The world file a campaign world was collected on, or None: ``worlds_dir/<name>.world``
    first (``report --worlds DIR``), then the runs' recorded ``world_file``, then the
    package's worlds/."""
    if worlds_dir is not None and (Path(worlds_dir) / f"{name}.world").is_file():
        return Path(worlds_dir) / f"{name}.world"
    world = campaign.worlds.get(name)
    recorded = [run.record.get("world_file") for run in (world.runs if world else [])]
    bases = [Path.cwd(), campaign.root, *campaign.root.resolve().parents]
    for text in dict.fromkeys(r for r in recorded if isinstance(r, str) and r):
        path = Path(text)
        candidates = [path] if path.is_absolute() else [base / path for base in bases]
        for candidate in candidates:
            if candidate.is_file():
                return candidate
    shipped = SHIPPED_WORLDS / f"{name}.world"
    return shipped if shipped.is_file() else None


class FeatureCache:
    """Feature vectors per (world, feature configuration), computed on first use.

    ``compute(world_name, card) -> features`` replaces the real computation (tests).
    """

    def __init__(self, campaign: Campaign, compute: Callable | None = None,
                 worlds_dir: Path | None = None):
        self.campaign = campaign
        self.worlds_dir = worlds_dir
        self._compute = compute or self._plan_features
        self._values: dict[tuple[str, str], dict[str, float]] = {}
        self._errors: dict[tuple[str, str], str] = {}
        self._worlds: dict[str, object] = {}

    def features(self, name: str, card: dict) -> dict[str, float]:
        """Features of world ``name`` with the card's configuration; InputError if impossible."""
        key = (name, json.dumps([card.get("feature_config") or {}, card.get("sightline")],
                                sort_keys=True))
        if key in self._errors:
            raise InputError(self._errors[key])
        if key not in self._values:
            try:
                self._values[key] = self._compute(name, card)
            except InputError as exc:
                self._errors[key] = exc.one_line()
                raise
        return self._values[key]

    def _plan_features(self, name: str, card: dict) -> dict[str, float]:
        from slam_predict.features.plan import plan_features
        from slam_predict.world.load import load_plan

        if name not in self._worlds:
            path = find_world_file(self.campaign, name, self.worlds_dir)
            if path is None:
                raise InputError(f"world file {name}.world not found (neither the runs' "
                                 f"world_file nor {SHIPPED_WORLDS}): give the folder holding "
                                 "it with 'report --worlds DIR' (the seed study's buildings: "
                                 "'slam-predict worlds import-thesis')")
            self._worlds[name] = load_plan(path)
        LOG.info("features of %s", name)
        return plan_features(self._worlds[name], card.get("feature_config") or {},
                             robot_sightline(card))


def recorded_runs(row: dict) -> int:
    """Runs of a summary row (0 when unknown)."""
    runs = float(row.get("runs", math.nan))
    return int(runs) if math.isfinite(runs) else 0


def predict_campaign(entry: ModelEntry, campaign: Campaign,
                     cache: FeatureCache) -> ModelPredictions:
    """Predictions of ``entry`` for every campaign world that has a summary row."""
    out = ModelPredictions()
    for row in campaign.summary_rows():
        name = row["world"]
        try:
            result = entry.store.predict(cache.features(name, entry.card))
        except InputError as exc:
            out.notes.append(f"{name}: no prediction ({exc.one_line()})")
            continue
        unmodelled = tuple(f"{c}: no model" for c in COMPONENTS
                           if result[c]["status"] == "no_model")  # said once per model
        out.notes += [f"{name}: {w}" for w in result["warnings"]
                      if w not in entry.store.notes and not w.startswith(unmodelled)]
        for component in COMPONENTS:
            out.items.append(Prediction.of(name, component, recorded_runs(row),
                                           float(row[component]), result[component]))
    return out


def _with_degrees(value: float, component: str) -> str:
    if UNITS[component] == "m":
        return H.number(value, 4)
    text = H.number(value, 5)
    return text if text == H.MISSING else f"{text} ({math.degrees(value):.3f}°)"


def _predicted_text(p: Prediction) -> str:
    if p.status == "below_range":
        return f"below the model's range (raw {H.number(p.raw_value, 4)})"
    return _with_degrees(p.value, p.component)


def _interval_text(p: Prediction) -> str:
    if not p.has_interval:
        return H.MISSING
    return f"{_with_degrees(p.low, p.component)} – {_with_degrees(p.high, p.component)}"


def predictions_table(items: list[Prediction]) -> str:
    """World × component rows: measured, predicted, interval, inside?, relative error."""
    rows = []
    for p in items:
        known = math.isfinite(p.measured) and p.has_interval
        rows.append([p.world, H.num_cell(p.runs, 0), p.component, UNITS[p.component],
                     H.Cell(_with_degrees(p.measured, p.component), numeric=True),
                     H.Cell(_predicted_text(p), numeric=True),
                     H.Cell(_interval_text(p), numeric=True),
                     ("yes" if p.inside else "no") if known else H.MISSING,
                     H.num_cell(100.0 * p.relative_error, 1)])
    header = ["world", "runs", "component", "unit", "measured (mean over runs)", "predicted",
              "interval", "measured inside", "error %"]
    return H.table(header, rows)


def coverage_line(items: list[Prediction], confidence) -> str:
    """How many measured values fall inside their intervals."""
    items = [p for p in items if p.has_interval]
    if not items:
        return ""
    inside = sum(p.inside for p in items)
    conf = f"{100 * float(confidence):g} %" if isinstance(confidence, (int, float)) else "?"
    return (f"<p>{inside} of {len(items)} measured values lie inside the model's {conf} "
            "interval.</p>")


def plot(items: list[Prediction], title: str) -> bytes | None:
    """Predicted-vs-measured figure of the items (None when there is nothing to plot)."""
    if not items:
        return None
    from slam_predict.report.figures import predicted_vs_measured

    points = {c: [vars(p) for p in items if p.component == c and p.status == "ok"
                  and p.has_interval and math.isfinite(p.measured)] for c in COMPONENTS}
    if not any(points.values()):
        return None
    return predicted_vs_measured(points, UNITS, LABELS, title)


def slam_config_hash(run) -> str | None:
    """A run's SLAM identity: run.json ``slam.params_hash``, or ``config_hashes.gmapping`` in
    records written before the ``slam`` entry."""
    return run.value("slam", "params_hash") or run.value("config_hashes", "gmapping")


def setup_notes(entry: ModelEntry, campaign: Campaign) -> list[str]:
    """Warn when the campaign's SLAM configuration is not the one the model learnt from."""
    card_hash = str(entry.card.get("slam_config_hash", ""))
    hashes = {str(h) for h in map(slam_config_hash, campaign.runs) if h}
    if hashes and not card_hash:
        return [f"the model's card does not record the GMapping configuration it learnt "
                f"from: it cannot be checked against this campaign's "
                f"({', '.join(sorted(hashes))})"]
    if hashes and card_hash not in hashes:
        return [f"the model learnt GMapping errors of SLAM configuration '{card_hash}' "
                f"(setting {entry.card.get('setting')}); this campaign ran configuration(s) "
                f"{', '.join(sorted(hashes))}: differences include the set-up, not only the "
                "model's error"]
    return []


def predictions_section(entry: ModelEntry, campaign: Campaign, cache: FeatureCache) -> str:
    """Table, coverage count, figure and notes of one model on the campaign's worlds."""
    if entry.store is None:
        return ""
    result = predict_campaign(entry, campaign, cache)
    unmodelled = sorted({p.component for p in result.items if p.status == "no_model"},
                        key=COMPONENTS.index)
    result.items = [p for p in result.items if p.status != "no_model"]
    if unmodelled:
        result.notes.insert(0, f"{', '.join(unmodelled)}: not predicted, no model of "
                               f"{entry.name} beats the training mean (evaluation R² ≤ 0)")
    single = [r["world"] for r in campaign.summary_rows() if recorded_runs(r) == 1]
    extra = ([f"{', '.join(single)}: one run only, so the measured std components are 0 by "
              "definition"] if single and result.items else [])
    body = (predictions_table(result.items) if result.items else "")
    body += coverage_line(result.items, entry.card.get("confidence"))
    png = plot(result.items, f"{entry.name}: predicted vs measured on this campaign")
    if png:
        body += H.image(png, f"predicted vs measured, model {entry.name}",
                        "Each point is one world: measured = mean over its runs; bar = the "
                        "model's interval; dashed line = perfect prediction.")
    body += H.notes(setup_notes(entry, campaign) + plan_model_robot_note(campaign) + extra
                    + result.notes)
    return H.section(f"Predictions of {entry.name} for this campaign's worlds", body, level=3)


def plan_model_robot_note(campaign: Campaign) -> list[str]:
    """The note a plan-only model's predictions get when the runs record their robots."""
    robots: dict[str, int] = {}
    for run in campaign.runs:
        if isinstance(run.record.get("sensor"), dict):
            text = robot_text(run.record["sensor"])
            robots[text] = robots.get(text, 0) + 1
    if not robots:
        return []
    listing = "; ".join(f"{text} ({n} runs)" for text, n in robots.items())
    return [f"this plan-only model does not take the robot into account: it predicts the "
            f"errors of its training runs' robot, whatever robot these runs used ({listing}); "
            "the differences include the robot, not only the model's error. A robot-aware "
            "model (e.g. models/own-robots) scores each run with its own robot"]


def robot_sightline(card: dict[str, Any]) -> dict[str, Any] | None:
    """The sight-line configuration a robot-aware card's features need (None otherwise)."""
    stored = card.get("sightline")
    if not isinstance(stored, dict):
        return None
    return {k: v for k, v in stored.items() if k != "ranges_m"}
