"""Robot campaign run records → RUN rows and POINT rows (issue #18).

A campaign folder holds ``<world>/run_NNN/run.json``, one robot configuration per run. A RUN
row is one run: ``world, run_index, seed, config, point, replicate``, the robot inputs
(:data:`~slam_predict.learn.robot.inputs.ROBOT_INPUTS`; the range capped at the maxUrange of the
run's GMapping settings, :mod:`~slam_predict.learn.robot.domain`), ``coverage`` and the run's
``trans_mean`` (m) and ``rot_mean`` (rad) — its mean relation errors. Runs of the design carry
``"design": {"config", "point", "replicate"}``; other runs (``collect --robot``) get
config = :func:`slam_predict.sensor.sensor_hash` of their ``sensor`` dict, point =
``world/config`` and replicate = their rank by run_index within the point.

A POINT is one building × robot configuration: its runs grouped by :func:`point_groups`, its
four components by :func:`point_targets` — ``trans_mean``/``rot_mean`` the mean over the
point's runs, ``trans_std``/``rot_std`` their sample standard deviation (ddof = 1; NaN with one
run). POINT rows are rows of the one learning dataset (:class:`slam_predict.learn.dataset.
Dataset`, built by :mod:`slam_predict.learn.robot.rundata`).

Each run's SLAM algorithm is run.json's ``slam.type`` (gmapping when absent); the campaigns are
read for one algorithm (``slam``): runs of another are left out, counted under
``SLAM <name>``.

Runs with ``coverage`` below the minimum (``min_coverage``; config/robot_learning.yaml: 0.5, the
failed-exploration rule ``metric.runs.MIN_COVERAGE``)
or without a usable metric are skipped, logged and counted; a missing or malformed record is
a one-line :class:`InputError` naming the file.
"""
from __future__ import annotations

import json
import logging
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from slam_predict.errors import InputError
from slam_predict.learn.card import DEFAULT_SLAM, check_slam
from slam_predict.learn.dataset import COMPONENTS
from slam_predict.learn.robot.inputs import (
    ROBOT_INPUTS,
    inputs_from_sensor,
    odom_model_of,
)
from slam_predict.metric.runs import MIN_COVERAGE, sample_std
from slam_predict.words import plural

LOG = logging.getLogger(__name__)
RUN_TARGETS = ("trans_mean", "rot_mean")        # per-run metric values (m, rad)
REQUIRED = ("world", "run_index", "seed", "coverage", "sensor")
RUN_COLUMNS = ("world", "run_index", "seed", "config", "point", "replicate", *ROBOT_INPUTS,
               "coverage", *RUN_TARGETS)


@dataclass
class RunRow:
    """One run: identity, robot inputs, coverage (share), mean errors (m, rad)."""

    world: str
    run_index: int
    seed: int
    config: str
    point: str
    replicate: int | None
    robot: dict[str, float]
    coverage: float
    trans_mean: float
    rot_mean: float
    config_hashes: dict[str, str] = field(default_factory=dict)
    source: str = ""
    max_urange_m: float | None = None    # GMapping's maxUrange of the run's settings, m
    odom_model: str = ""                 # the sensor's odometry model (inputs.odom_model_of)
    slam: str = DEFAULT_SLAM             # the run's SLAM algorithm (run.json slam.type)
    designed: bool = True                # run.json has a ``design`` entry (collect --design)


# ----------------------------------------------------------------------------- run records

def find_records(folders: Sequence[os.PathLike | str]) -> list[Path]:
    """Every ``<world>/run_NNN/run.json`` under the campaign folders (a world folder's
    ``run_NNN/run.json`` too), sorted; InputError for a missing folder or one without runs."""
    found: list[Path] = []
    for folder in map(Path, folders):
        if not folder.is_dir():
            raise InputError("campaign folder not found", folder)
        files = sorted(folder.glob("*/run_*/run.json")) or sorted(folder.glob("run_*/run.json"))
        if not files:
            raise InputError("no run.json found (expected WORLD/run_NNN/run.json)", folder)
        found += files
    return found


def read_record(path: os.PathLike | str) -> dict[str, Any]:
    """A run.json as a dict; InputError naming the file when unreadable or incomplete."""
    try:
        record = json.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise InputError(f"unreadable run record ({exc.__class__.__name__})", path) from None
    if not isinstance(record, dict):
        raise InputError("run record is not a JSON object", path)
    missing = [key for key in REQUIRED if key not in record]
    if missing:
        raise InputError(f"run record has no '{missing[0]}'", path)
    return record


def slam_of_record(record: Mapping[str, Any]) -> str:
    """The SLAM algorithm of a run record: ``slam.type``, gmapping when it names none."""
    slam = record.get("slam")
    return str(slam.get("type") or DEFAULT_SLAM) if isinstance(slam, Mapping) else DEFAULT_SLAM


def slam_records(folders: Sequence[os.PathLike | str], slam: str = DEFAULT_SLAM,
                 skipped: dict[str, int] | None = None):
    """(path, record) of every run record of the campaign folders whose SLAM algorithm is
    ``slam``; the others are counted in ``skipped`` under ``SLAM <name>``."""
    check_slam(slam)
    for path in find_records(folders):
        record = read_record(path)
        other = slam_of_record(record)
        if other != slam:
            if skipped is not None:
                skipped[f"SLAM {other}"] = skipped.get(f"SLAM {other}", 0) + 1
            continue
        yield path, record


def record_worlds(folders: Sequence[os.PathLike | str], slam: str = DEFAULT_SLAM) -> set[str]:
    """The buildings of every run record of SLAM algorithm ``slam`` in the campaign folders
    (usable or not)."""
    return {str(record["world"]) for _, record in slam_records(folders, slam)}


def _finite(value: Any) -> float | None:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value) if math.isfinite(value) else None


def _integer(record: Mapping[str, Any], key: str, path) -> int:
    value = record[key]
    if isinstance(value, bool) or not isinstance(value, int):
        raise InputError(f"'{key}' must be an integer, got {value!r}", path)
    return value


def _design(record: Mapping[str, Any], world: str, config: str, path):
    """(config, point, replicate) from ``design`` (defaults: sensor hash, world/config, None)."""
    design = record.get("design")
    if design is None:
        return config, f"{world}/{config}", None
    if not isinstance(design, Mapping):
        raise InputError("'design' must be a mapping", path)
    for key in ("config", "point", "replicate"):
        if key not in design:
            raise InputError(f"'design' has no '{key}'", path)
    if not isinstance(design["config"], str) or not isinstance(design["point"], str) \
            or not design["config"] or not design["point"]:
        raise InputError("'design.config' and 'design.point' must be non-empty strings", path)
    return design["config"], design["point"], _integer(design, "replicate", path)


def design_entry(record: Mapping[str, Any], path) -> tuple[str, str, int | None]:
    """(config, point, replicate) of a record: its ``design`` entry, else (the hash of its
    ``sensor``, world/hash, None)."""
    from slam_predict.sensor import sensor_hash

    return _design(record, str(record["world"]), sensor_hash(record["sensor"]), path)


def skip_reason(record: Mapping[str, Any], min_coverage: float, path) -> str | None:
    """Why a complete record is not used ('low coverage', 'no metric', 'error <= 0'), or None."""
    coverage = _finite(record["coverage"])
    if coverage is None:
        raise InputError(f"'coverage' must be a finite number, got {record['coverage']!r}", path)
    if coverage < min_coverage:
        return "low coverage"
    metric = record.get("metric")
    if not isinstance(metric, Mapping):
        return "no metric"
    values = [_finite(metric.get(key)) for key in RUN_TARGETS]
    if any(v is None for v in values):
        return "no metric"
    if any(v <= 0 for v in values):  # type: ignore[operator]
        return "error <= 0"
    return None


def run_row(record: Mapping[str, Any], path, max_urange_m: float | None = None) -> RunRow:
    """The RUN row of a complete, usable record (range capped at ``max_urange_m`` m)."""
    world = record["world"]
    if not isinstance(world, str) or not world:
        raise InputError(f"'world' must be a non-empty string, got {world!r}", path)
    robot = inputs_from_sensor(record["sensor"], path, max_urange_m)
    odom_model = odom_model_of(record["sensor"], path)
    config, point, replicate = design_entry(record, path)
    hashes = record.get("config_hashes") if isinstance(record.get("config_hashes"), dict) else {}
    return RunRow(world=world, run_index=_integer(record, "run_index", path),
                  seed=_integer(record, "seed", path), config=config, point=point,
                  replicate=replicate, robot=robot, coverage=float(record["coverage"]),
                  trans_mean=float(record["metric"]["trans_mean"]),
                  rot_mean=float(record["metric"]["rot_mean"]),
                  config_hashes={str(k): str(v) for k, v in hashes.items()}, source=str(path),
                  max_urange_m=max_urange_m, odom_model=odom_model,
                  slam=slam_of_record(record), designed=record.get("design") is not None)


def read_runs(folders: Sequence[os.PathLike | str], min_coverage: float = MIN_COVERAGE,
              max_urange_m: float | None = None,
              slam: str = DEFAULT_SLAM) -> tuple[list[RunRow], dict[str, int]]:
    """(RUN rows, {skip reason: count}) of the campaign folders' runs of SLAM algorithm
    ``slam``, checked for consistency; ``max_urange_m``: GMapping's maxUrange, m, for every run
    (None: from each run's settings, :class:`~slam_predict.learn.robot.domain.
    MaxUrangeSource`)."""
    from slam_predict.learn.robot.domain import MaxUrangeSource, common_max_urange

    rows: list[RunRow] = []
    skipped: dict[str, int] = {}
    caps = MaxUrangeSource(max_urange_m)
    for path, record in slam_records(folders, slam, skipped):
        reason = skip_reason(record, min_coverage, path)
        if reason is not None:
            skipped[reason] = skipped.get(reason, 0) + 1
            LOG.debug("skipping %s: %s", path, reason)
            continue
        rows.append(run_row(record, path, caps.of_record(record, path)))
    for reason, count in sorted(skipped.items()):
        LOG.warning("skipped %s: %s%s", plural(count, "run"), reason,
                    f" (< {min_coverage:g})" if reason == "low coverage" else "")
    if not rows:
        raise InputError("no usable run (every run was skipped: "
                         + ", ".join(f"{n} {r}" for r, n in sorted(skipped.items())) + ")",
                         os.fspath(folders[0]))
    common_max_urange({r.source: r.max_urange_m for r in rows})
    common_odom_model(rows)
    _check_consistency(rows)
    _assign_replicates(rows)
    rows.sort(key=lambda r: (r.world, r.config, r.replicate, r.run_index, r.seed))
    return rows, skipped


def common_odom_model(rows: Sequence[RunRow]) -> str:
    """The runs' odometry model ('none' only when every run has none); InputError when runs
    mix ``uniform_per_run`` and ``fixed``, whose error numbers mean different robots."""
    models = {r.odom_model for r in rows if r.odom_model and r.odom_model != "none"}
    if len(models) > 1:
        first = {m: next(r.source for r in rows if r.odom_model == m) for m in sorted(models)}
        raise InputError("runs mix odometry models ("
                         + ", ".join(f"{m} in {src}" for m, src in first.items())
                         + "): their error numbers describe different robots; learn each "
                         "campaign on its own", rows[-1].source)
    return models.pop() if models else "none"


def _check_consistency(rows: Sequence[RunRow]) -> None:
    """InputError for a run listed twice, a configuration with two robots, or a point of two
    buildings or configurations."""
    seen: dict[tuple, str] = {}
    robot_of: dict[str, RunRow] = {}
    point_of: dict[str, RunRow] = {}
    for row in rows:
        key = (row.world, row.config, row.seed, row.run_index)
        if key in seen:
            raise InputError(f"run listed twice (also {seen[key]})", row.source)
        seen[key] = row.source
        first = robot_of.setdefault(row.config, row)
        if any(not math.isclose(first.robot[k], row.robot[k], rel_tol=1e-9, abs_tol=1e-12)
               for k in ROBOT_INPUTS):
            raise InputError(f"configuration '{row.config}' has other robot inputs than in "
                             f"{first.source}", row.source)
        other = point_of.setdefault(row.point, row)
        if (other.world, other.config) != (row.world, row.config):
            raise InputError(f"point '{row.point}' is {row.world} × {row.config} here but "
                             f"{other.world} × {other.config} in {other.source}", row.source)


def _assign_replicates(rows: Sequence[RunRow]) -> None:
    """Replicate numbers unique within each point: a run keeps its design replicate unless an
    earlier record of the point (by file path) holds it — a campaign pooled with another
    collected from the same design under another seed repeats the numbers —; runs without one
    or with a taken one get the lowest free numbers, by run_index."""
    by_point: dict[str, list[RunRow]] = {}
    for row in rows:
        by_point.setdefault(row.point, []).append(row)
    for members in by_point.values():
        given: set[int] = set()
        for row in sorted((r for r in members if r.replicate is not None),
                          key=lambda r: r.source):
            if row.replicate in given:
                row.replicate = None
            else:
                given.add(row.replicate)
        for row in sorted(members, key=lambda r: (r.run_index, r.seed, r.source)):
            if row.replicate is None:
                row.replicate = min(set(range(len(members) + 1)) - given)
                given.add(row.replicate)


def point_groups(runs: Sequence[RunRow]) -> dict[str, list[RunRow]]:
    """Point id → its runs, points in order of first appearance."""
    groups: dict[str, list[RunRow]] = {}
    for row in runs:
        groups.setdefault(row.point, []).append(row)
    return groups


def point_targets(members: Sequence[RunRow]) -> dict[str, float]:
    """The four components of a point's runs: the mean and the sample std
    (``SAMPLE_STD_DDOF``, NaN for one run) of their errors."""
    targets: dict[str, float] = {}
    for name in RUN_TARGETS:
        values = np.array([getattr(r, name) for r in members])
        targets[name] = float(values.mean())
        targets[name.replace("_mean", "_std")] = sample_std(values)
    return {c: targets[c] for c in COMPONENTS}
