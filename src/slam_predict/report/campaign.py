"""A collection campaign as the report sees it: worlds, runs, their records and what is missing.

Reads ``DATA/<world>/run_NNN/run.json`` (see :mod:`slam_predict.collect.record`) and
``DATA/summary.csv`` (:mod:`slam_predict.collect.summary`). The per-building rows are recomputed
from the run records with :func:`slam_predict.collect.summary.building_row` (the code that writes
summary.csv), and compared with the CSV: a stale or missing CSV is a note, not an error. Runs
with an unreadable run.json, interrupted runs and records lacking fields are notes too; only a
folder that holds neither run records nor a summary.csv is refused.
"""
from __future__ import annotations

import csv
import json
import logging
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

from slam_predict.collect.summary import COLUMNS, KEY_COLUMNS, building_row
from slam_predict.errors import InputError

LOG = logging.getLogger(__name__)
RUN_DIR = re.compile(r"^run_\d{3}$")
# run.json fields building_row needs: (path of keys, may be null in a valid record).
SUMMARY_FIELDS = ((("metric", "trans_mean"), False), (("metric", "rot_mean"), False),
                  (("metric", "trans_sqr_mean"), False), (("metric", "rot_sqr_mean"), False),
                  (("distance_m",), False), (("rotation_rad",), False),
                  (("coverage",), True), (("sim_duration_s",), True))
TRAJECTORY_FILES = ("ground_truth.tum", "slam.tum", "odom.tum")
CSV_TOLERANCE = 1e-6  # relative; summary.csv keeps 9 significant digits


@dataclass
class Run:
    """One complete run folder and its run.json."""

    world: str
    run_id: str
    folder: Path
    record: dict

    def has(self, name: str) -> bool:
        return (self.folder / name).is_file()

    @property
    def has_map(self) -> bool:
        return self.has("map.yaml")

    @property
    def has_trajectories(self) -> bool:
        return all(self.has(name) for name in TRAJECTORY_FILES)

    def value(self, *keys: str):
        """A nested run.json value, or None when absent."""
        value = self.record
        for key in keys:
            if not isinstance(value, dict) or key not in value:
                return None
            value = value[key]
        return value


@dataclass
class WorldRuns:
    """The runs of one world, its summary row and the problems found while reading it."""

    name: str
    runs: list[Run] = field(default_factory=list)
    row: dict[str, float] | None = None
    notes: list[str] = field(default_factory=list)


@dataclass
class Campaign:
    """A campaign folder: worlds by name, summary.csv rows, campaign-level notes."""

    root: Path
    worlds: dict[str, WorldRuns]
    csv_rows: dict[str, dict[str, str]]
    notes: list[str] = field(default_factory=list)

    @property
    def runs(self) -> list[Run]:
        return [run for world in self.worlds.values() for run in world.runs]

    def summary_rows(self) -> list[dict]:
        """Per-building rows: recomputed ones, or the CSV's for worlds without run records."""
        rows = []
        for name in sorted(set(self.worlds) | set(self.csv_rows)):
            world = self.worlds.get(name)
            if world is not None and world.row is not None:
                rows.append(world.row)
            elif name in self.csv_rows:
                rows.append(_csv_numbers(self.csv_rows[name]))
        return rows


def load_campaign(path) -> Campaign:
    """Read a campaign folder; InputError when it is missing or is not a campaign."""
    root = Path(path)
    if not root.exists():
        raise InputError("campaign folder not found", root)
    if not root.is_dir():
        raise InputError("not a folder (expected a campaign written by 'slam-predict collect')",
                         root)
    notes: list[str] = []
    csv_rows = read_summary_csv(root / "summary.csv", notes)
    worlds = {}
    for folder in sorted(p for p in root.iterdir() if p.is_dir() and not p.name.startswith(".")):
        world = read_world(folder)
        if world.runs or world.notes:
            worlds[folder.name] = world
    if not any(w.runs for w in worlds.values()) and not csv_rows:
        raise InputError("not a slam-predict campaign (no summary.csv and no "
                         "<world>/run_NNN/run.json)", root)
    campaign = Campaign(root, worlds, csv_rows, notes)
    compare_with_csv(campaign)
    return campaign


def read_world(folder: Path) -> WorldRuns:
    """The complete runs below ``folder`` and their summary row."""
    world = WorldRuns(folder.name)
    leftovers = list(folder.glob(".run_*.tmp"))
    if leftovers:
        world.notes.append(f"{len(leftovers)} interrupted run(s) (temporary folders) ignored")
    for run_dir in sorted(p for p in folder.iterdir() if p.is_dir() and RUN_DIR.match(p.name)):
        try:
            record = json.loads((run_dir / "run.json").read_text(encoding="utf-8"))
        except FileNotFoundError:
            world.notes.append(f"{run_dir.name}: no run.json (incomplete run), ignored")
            continue
        except (OSError, UnicodeDecodeError, ValueError) as exc:
            world.notes.append(f"{run_dir.name}: run.json unreadable ({exc.__class__.__name__}), "
                               "ignored")
            continue
        if not isinstance(record, dict):
            world.notes.append(f"{run_dir.name}: run.json is not a JSON object, ignored")
            continue
        world.runs.append(Run(folder.name, run_dir.name, run_dir, record))
    usable = []
    for run in world.runs:
        lacking = missing_fields(run.record)
        if run.record.get("metric") is None and run.record.get("metric_note"):
            world.notes.append(f"{run.run_id}: no error measured ({run.record['metric_note']}); "
                               "left out of the summary")
        elif lacking:
            world.notes.append(f"{run.run_id}: run.json lacks {', '.join(lacking)}; left out of "
                               "the summary")
        else:
            usable.append(run)
    if usable:
        world.row = building_row(world.name, [summary_ready(run.record) for run in usable])
    return world


def missing_fields(record: dict) -> list[str]:
    """Dotted names of the summary fields a run.json lacks (or holds as non-numbers)."""
    lacking = []
    for keys, nullable in SUMMARY_FIELDS:
        value = record
        for key in keys:
            value = value.get(key) if isinstance(value, dict) else None
        if value is None and nullable:
            continue
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            lacking.append(".".join(keys))
    return lacking


def summary_ready(record: dict) -> dict:
    """The record with nullable summary fields (coverage, sim time) turned from null to NaN."""
    out = dict(record)
    for keys, nullable in SUMMARY_FIELDS:
        if nullable and len(keys) == 1 and out.get(keys[0]) is None:
            out[keys[0]] = math.nan
    return out


def read_summary_csv(path: Path, notes: list[str]) -> dict[str, dict[str, str]]:
    """summary.csv rows by world ({} with a note when the file is absent or unreadable)."""
    if not path.is_file():
        notes.append("summary.csv is missing; the per-building table is computed from the "
                     "run records")
        return {}
    try:
        with open(path, newline="", encoding="utf-8") as handle:
            rows = list(csv.DictReader(handle))
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        notes.append(f"summary.csv unreadable ({exc.__class__.__name__}); ignored")
        return {}
    if rows and "world" not in rows[0]:
        notes.append("summary.csv has no 'world' column; ignored")
        return {}
    return {row["world"]: row for row in rows if row.get("world")}


def compare_with_csv(campaign: Campaign) -> None:
    """Notes for worlds whose summary.csv row is missing or differs from the run records."""
    if not campaign.csv_rows:
        return
    stale = []
    for name, world in campaign.worlds.items():
        if world.row is None:
            continue
        row = campaign.csv_rows.get(name)
        if row is None:
            stale.append(f"{name} (not in the CSV)")
            continue
        for column in ("runs", "trans_mean", "trans_std", "rot_mean", "rot_std"):
            if not _close(row.get(column), world.row[column]):
                stale.append(f"{name} ({column} {row.get(column)} in the CSV, "
                             f"{world.row[column]:.9g} from the runs)")
                break
    for name in campaign.csv_rows:
        if name not in campaign.worlds or campaign.worlds[name].row is None:
            campaign.notes.append(f"{name}: in summary.csv but no usable run record; its row "
                                  "is taken from the CSV")
    if stale:
        campaign.notes.append("summary.csv is stale for " + "; ".join(stale) + " — the table "
                              "uses the run records (re-run 'slam-predict collect' to refresh it)")


def _close(text: str | None, value: float) -> bool:
    try:
        csv_value = float(text)
    except (TypeError, ValueError):
        return False
    if math.isnan(csv_value) and math.isnan(value):
        return True
    return math.isclose(csv_value, value, rel_tol=CSV_TOLERANCE, abs_tol=1e-12)


def _csv_numbers(row: dict[str, str]) -> dict:
    """A summary.csv row with its numeric columns as floats (NaN when empty or bad)."""
    out: dict = {key: row.get(key, "") for key in KEY_COLUMNS}
    for column in (c for c in COLUMNS if c not in KEY_COLUMNS):
        try:
            out[column] = float(row.get(column, ""))
        except (TypeError, ValueError):
            out[column] = math.nan
    return out
