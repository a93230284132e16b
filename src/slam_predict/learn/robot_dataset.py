"""Robot-aware learning data: campaign run records → RUN rows and POINT rows (issue #18).

A campaign folder holds ``<world>/run_NNN/run.json``, one robot configuration per run. A RUN
row is one run: ``world, run_index, seed, config, point, replicate``, the robot inputs
(:data:`~slam_predict.learn.robot_inputs.ROBOT_INPUTS`; the range capped at the maxUrange of the
run's GMapping settings, :mod:`~slam_predict.learn.robot_domain`), ``coverage`` and the run's
``trans_mean`` (m) and ``rot_mean`` (rad) — its mean relation errors. Runs of the design carry
``"design": {"config", "point", "replicate"}``; other runs (``collect --robot``) get
config = :func:`slam_predict.sensor.sensor_hash` of their ``sensor`` dict, point =
``world/config`` and replicate = their rank by run_index within the point.

A POINT row is one building × robot configuration: ``world, config, point, runs``, the robot
inputs and the four components — ``trans_mean``/``rot_mean`` the mean over the point's runs,
``trans_std``/``rot_std`` their sample standard deviation (ddof = 1; NaN with one run).

Runs with ``coverage`` below the minimum (default 0.9) or without a usable metric are skipped,
logged and counted; a missing or malformed record is a one-line :class:`InputError` naming
the file. Plan features are joined per world (a feature table, or computed from plans).
"""
from __future__ import annotations

import csv
import io
import json
import logging
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from slam_predict.errors import InputError, did_you_mean
from slam_predict.learn.dataset import COMPONENTS
from slam_predict.learn.robot_inputs import (
    ROBOT_INPUTS,
    angular_resolution_deg,
    inputs_from_sensor,
)
from slam_predict.words import plural

LOG = logging.getLogger(__name__)
RUN_TARGETS = ("trans_mean", "rot_mean")        # per-run metric values (m, rad)
REQUIRED = ("world", "run_index", "seed", "coverage", "sensor")
RUN_COLUMNS = ("world", "run_index", "seed", "config", "point", "replicate", *ROBOT_INPUTS,
               "coverage", *RUN_TARGETS)
POINT_COLUMNS = ("world", "config", "point", "runs", *ROBOT_INPUTS, *COMPONENTS)


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
    resolution_deg: float = math.nan
    config_hashes: dict[str, str] = field(default_factory=dict)
    source: str = ""
    max_urange_m: float | None = None    # GMapping's maxUrange of the run's settings, m


@dataclass
class PointRow:
    """One building × configuration: run count, robot inputs, the four components."""

    world: str
    config: str
    point: str
    runs: int
    robot: dict[str, float]
    targets: dict[str, float]


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
    from slam_predict.sensor import sensor_hash

    world = record["world"]
    if not isinstance(world, str) or not world:
        raise InputError(f"'world' must be a non-empty string, got {world!r}", path)
    robot = inputs_from_sensor(record["sensor"], path, max_urange_m)
    config, point, replicate = _design(record, world, sensor_hash(record["sensor"]), path)
    hashes = record.get("config_hashes") if isinstance(record.get("config_hashes"), dict) else {}
    return RunRow(world=world, run_index=_integer(record, "run_index", path),
                  seed=_integer(record, "seed", path), config=config, point=point,
                  replicate=replicate, robot=robot, coverage=float(record["coverage"]),
                  trans_mean=float(record["metric"]["trans_mean"]),
                  rot_mean=float(record["metric"]["rot_mean"]),
                  resolution_deg=angular_resolution_deg(record["sensor"], path),
                  config_hashes={str(k): str(v) for k, v in hashes.items()}, source=str(path),
                  max_urange_m=max_urange_m)


def read_runs(folders: Sequence[os.PathLike | str], min_coverage: float = 0.9,
              max_urange_m: float | None = None) -> tuple[list[RunRow], dict[str, int]]:
    """(RUN rows, {skip reason: count}) of the campaign folders, checked for consistency;
    ``max_urange_m``: GMapping's maxUrange, m, for every run (None: from each run's settings,
    :class:`~slam_predict.learn.robot_domain.MaxUrangeSource`)."""
    from slam_predict.learn.robot_domain import MaxUrangeSource, common_max_urange

    rows: list[RunRow] = []
    skipped: dict[str, int] = {}
    caps = MaxUrangeSource(max_urange_m)
    for path in find_records(folders):
        record = read_record(path)
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
    _check_consistency(rows)
    _assign_replicates(rows)
    rows.sort(key=lambda r: (r.world, r.config, r.replicate, r.run_index, r.seed))
    return rows, skipped


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
    """Runs without a design replicate: their rank by run_index within the point."""
    by_point: dict[str, list[RunRow]] = {}
    for row in rows:
        by_point.setdefault(row.point, []).append(row)
    for members in by_point.values():
        given = {r.replicate for r in members if r.replicate is not None}
        for rank, row in enumerate(sorted(members, key=lambda r: (r.run_index, r.seed))):
            if row.replicate is None:
                row.replicate = rank
                while row.replicate in given:
                    row.replicate += 1
                given.add(row.replicate)


def point_rows(runs: Sequence[RunRow]) -> list[PointRow]:
    """POINT rows: per point the mean and the sample std (ddof 1, NaN for one run) of the
    runs' errors, in order of first appearance."""
    groups: dict[str, list[RunRow]] = {}
    for row in runs:
        groups.setdefault(row.point, []).append(row)
    out = []
    for point, members in groups.items():
        targets: dict[str, float] = {}
        for name in RUN_TARGETS:
            values = np.array([getattr(r, name) for r in members])
            targets[name] = float(values.mean())
            std = name.replace("_mean", "_std")
            targets[std] = float(values.std(ddof=1)) if len(values) > 1 else math.nan
        first = members[0]
        out.append(PointRow(first.world, first.config, point, len(members), dict(first.robot),
                            {c: targets[c] for c in COMPONENTS}))
    return out


# ----------------------------------------------------------------------------- joined tables

@dataclass
class RobotTables:
    """Numeric RUN and POINT tables over ``names`` = plan features + ROBOT_INPUTS.

    Attributes:
        names: input column names.
        run_X, point_X: (n_runs, d) and (n_points, d) inputs (plan features raw, robot inputs
            in their units).
        run_y: {trans_mean, rot_mean: (n_runs,)} run errors (m, rad).
        point_y: {component: (n_points,)} point values (m, rad; NaN stds for one run).
        run_point: (n_runs,) index of each run's point; point_runs: (n_points,) run counts.
        point_world, point_config: (n_points,) building and configuration of each point.
    """

    names: list[str]
    run_X: np.ndarray
    run_y: dict[str, np.ndarray]
    run_point: np.ndarray
    point_X: np.ndarray
    point_y: dict[str, np.ndarray]
    point_runs: np.ndarray
    point_world: np.ndarray
    point_config: np.ndarray

    @property
    def run_world(self) -> np.ndarray:
        """(n_runs,) building of each run."""
        return self.point_world[self.run_point]

    def subset(self, points: Sequence[int] | np.ndarray) -> RobotTables:
        """The tables restricted to the POINT rows ``points`` (indices) and their runs."""
        points = np.asarray(points, dtype=int)
        new_index = np.full(len(self.point_X), -1)
        new_index[points] = np.arange(len(points))
        runs = np.flatnonzero(new_index[self.run_point] >= 0)
        return RobotTables(list(self.names), self.run_X[runs],
                           {k: v[runs] for k, v in self.run_y.items()},
                           new_index[self.run_point[runs]], self.point_X[points],
                           {k: v[points] for k, v in self.point_y.items()},
                           self.point_runs[points], self.point_world[points],
                           self.point_config[points])


@dataclass
class RobotDataset:
    """RUN and POINT rows with the plan features of their buildings.

    Attributes:
        runs, points: the rows (only buildings that have features).
        features: building → {feature: value} for every building with runs.
        feature_version: the features' version string.
        skipped: skip reason → number of runs.
    """

    runs: list[RunRow]
    points: list[PointRow]
    features: dict[str, dict[str, float]]
    feature_version: str
    skipped: dict[str, int] = field(default_factory=dict)

    @property
    def worlds(self) -> list[str]:
        """The buildings, sorted."""
        return sorted({p.world for p in self.points})

    @property
    def configs(self) -> dict[str, dict[str, float]]:
        """Configuration id → robot inputs, sorted by id."""
        return {p.config: dict(p.robot) for p in sorted(self.points, key=lambda p: p.config)}

    @property
    def max_urange_m(self) -> float | None:
        """GMapping's maxUrange of the runs, m (one value, checked by :func:`read_runs`)."""
        return self.runs[0].max_urange_m if self.runs else None

    @property
    def resolutions_deg(self) -> list[float]:
        """The distinct laser angular resolutions of the runs, deg, rounded to 0.01 deg
        (fov/0.5 + 1 beams, the count rounded, give 0.4997–0.5003 deg: all 0.5)."""
        return sorted({round(r.resolution_deg, 2) for r in self.runs})

    def feature_names(self) -> list[str]:
        """Every plan feature name of the table (its order)."""
        first = self.features[self.worlds[0]]
        return [k for k in first if k != "feature_version"]

    def check_features(self, names: Sequence[str]) -> list[str]:
        """``names`` (all features when empty), checked: known and finite for every building."""
        known = self.feature_names()
        names = list(names) or known
        for name in names:
            if name not in known:
                raise InputError(f"plan feature '{name}' is not in the feature table"
                                 + did_you_mean(name, known))
            for world in self.worlds:
                if not math.isfinite(float(self.features[world].get(name, math.nan))):
                    raise InputError(f"plan feature '{name}' is missing for building '{world}'")
        return names

    def tables(self, plan_features: Sequence[str]) -> RobotTables:
        """The numeric tables over ``plan_features`` (checked) + ROBOT_INPUTS."""
        plan = self.check_features(plan_features)
        names = plan + list(ROBOT_INPUTS)
        index = {p.point: i for i, p in enumerate(self.points)}

        def row(world: str, robot: Mapping[str, float]) -> list[float]:
            return [float(self.features[world][n]) for n in plan] + [robot[k] for k in
                                                                     ROBOT_INPUTS]
        return RobotTables(
            names=names,
            run_X=np.array([row(r.world, r.robot) for r in self.runs], dtype=float),
            run_y={k: np.array([getattr(r, k) for r in self.runs]) for k in RUN_TARGETS},
            run_point=np.array([index[r.point] for r in self.runs], dtype=int),
            point_X=np.array([row(p.world, p.robot) for p in self.points], dtype=float),
            point_y={c: np.array([p.targets[c] for p in self.points]) for c in COMPONENTS},
            point_runs=np.array([p.runs for p in self.points], dtype=int),
            point_world=np.array([p.world for p in self.points]),
            point_config=np.array([p.config for p in self.points]))

    def config_hashes(self) -> dict[str, list[str]]:
        """Component configuration (gmapping, sim, ...) → the distinct hashes of the runs."""
        out: dict[str, set[str]] = {}
        for run in self.runs:
            for key, value in run.config_hashes.items():
                out.setdefault(key, set()).add(value)
        return {k: sorted(v) for k, v in sorted(out.items())}


def build_dataset(runs: Sequence[RunRow], skipped: Mapping[str, int],
                  features: Mapping[str, Mapping[str, Any]],
                  feature_version: str) -> RobotDataset:
    """Join the RUN rows of :func:`read_runs` with the plan features (exact building names).

    Buildings without features are left out (logged, counted in ``skipped``); fewer than 2
    left is an InputError.
    """
    skipped = dict(skipped)
    have = [r for r in runs if r.world in features]
    missing = sorted({r.world for r in runs} - set(features))
    if missing:
        LOG.warning("%s without plan features left out: %s",
                    plural(len(missing), "building"), ", ".join(missing))
        skipped["no plan features"] = len(runs) - len(have)
    worlds = sorted({r.world for r in have})
    if len(worlds) < 2:
        raise InputError(f"only {plural(len(worlds), 'building')} with both runs and plan "
                         "features (need 2 or more)")
    return RobotDataset(list(have), point_rows(have), {w: dict(features[w]) for w in worlds},
                        feature_version, skipped)


# ----------------------------------------------------------------------------- CSV texts

def _cell(value: Any) -> str:
    if isinstance(value, float):
        return "" if math.isnan(value) else repr(value)
    return str(value)


def _csv(header: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(header)
    for row in rows:
        writer.writerow([_cell(v) for v in row])
    return out.getvalue()


def runs_csv(data: RobotDataset) -> str:
    """The RUN table as CSV (RUN_COLUMNS)."""
    return _csv(RUN_COLUMNS, [[r.world, r.run_index, r.seed, r.config, r.point, r.replicate,
                               *(r.robot[k] for k in ROBOT_INPUTS), r.coverage, r.trans_mean,
                               r.rot_mean] for r in data.runs])


def points_csv(data: RobotDataset, plan_features: Sequence[str] = ()) -> str:
    """The POINT table as CSV (POINT_COLUMNS, then the plan features)."""
    names = list(plan_features)
    return _csv((*POINT_COLUMNS, *names),
                [[p.world, p.config, p.point, p.runs, *(p.robot[k] for k in ROBOT_INPUTS),
                  *(p.targets[c] for c in COMPONENTS),
                  *(float(data.features[p.world][n]) for n in names)] for p in data.points])


# ----------------------------------------------------------------------------- plan features

def plan_features(worlds: Sequence[str], features_csv: os.PathLike | str | None = None,
                  worlds_dir: os.PathLike | str | None = None,
                  feature_config: Mapping[str, Any] | None = None,
                  feature_version: str | None = None,
                  n_jobs: int = 1) -> tuple[dict[str, dict[str, float]], str, dict[str, Any]]:
    """(building → features, feature version, full feature configuration) from a feature
    table (``learn dataset``'s format; version from its column or ``feature_version``) or
    computed on the plans in ``worlds_dir`` with ``feature_config``."""
    from slam_predict.learn import dataset as ds

    if worlds_dir is not None:
        from slam_predict.learn.featurize import features_from_worlds, full_feature_config

        config = full_feature_config(feature_config)
        features, version = features_from_worlds(worlds_dir, worlds, config, n_jobs)
        return features, version, config
    if features_csv is None:
        raise InputError("give a feature table or a worlds folder")
    config = dict(ds.read_meta(features_csv).get("feature_config") or {})
    table = ds.read_feature_table(features_csv)
    versions = {str(v["feature_version"]) for v in table.values() if "feature_version" in v}
    if feature_version:
        versions = {feature_version}
    if len(versions) != 1 or not next(iter(versions)):
        raise InputError("features table needs one feature_version (column or "
                         "--feature-version)", features_csv)
    clean = {w: {k: v for k, v in vec.items() if k != "feature_version"}
             for w, vec in table.items()}
    return clean, versions.pop(), config
