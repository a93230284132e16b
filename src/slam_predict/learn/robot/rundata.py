"""Robot-aware learning data: the RUN rows of design campaigns
(:mod:`slam_predict.learn.robot.records`) with their buildings' plan features, as numeric tables
and as POINT rows of the one learning dataset (:class:`slam_predict.learn.dataset.Dataset`:
one row per building × robot configuration, with the robot columns).

:class:`RunData` holds the runs and the plan features (a feature table, or computed from plans,
:func:`plan_features`); :meth:`RunData.point_dataset` gives the POINT rows (written as the
evaluation's ``points.csv`` and a model folder's ``training_points.csv`` by
:func:`slam_predict.learn.dataset.to_csv_text`), :meth:`RunData.tables` the numeric RUN and
POINT tables the models are fitted on.
"""
from __future__ import annotations

import csv
import io
import logging
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from slam_predict.errors import InputError, did_you_mean
from slam_predict.features.sightline import COLUMN_PREFIX, PLAN_COLUMNS, curve_columns
from slam_predict.learn.card import ROBOT_KIND
from slam_predict.learn.dataset import COMPONENTS, Dataset
from slam_predict.learn.robot.inputs import (
    ALL_ROBOT_INPUTS,
    DERIVED_INPUTS,
    RESOLUTION_INPUT,
    ROBOT_INPUTS,
    derived_inputs,
)
from slam_predict.learn.robot.records import (
    RUN_COLUMNS,
    RUN_TARGETS,
    RunRow,
    point_groups,
    point_targets,
)
from slam_predict.words import plural

LOG = logging.getLogger(__name__)


# ----------------------------------------------------------------------------- joined tables

@dataclass
class RobotTables:
    """Numeric RUN and POINT tables over ``names`` = plan features [+ DERIVED_INPUTS] + the
    robot inputs (ROBOT_INPUTS [+ RESOLUTION_INPUT]).

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
class RunData:
    """RUN rows with the plan features of their buildings.

    Attributes:
        runs: the rows (only buildings that have features; one SLAM algorithm).
        features: building → {feature: value} for every building with runs.
        feature_version: the features' version string.
        skipped: skip reason → number of runs.
    """

    runs: list[RunRow]
    features: dict[str, dict[str, float]]
    feature_version: str
    skipped: dict[str, int] = field(default_factory=dict)

    @property
    def worlds(self) -> list[str]:
        """The buildings, sorted."""
        return sorted({r.world for r in self.runs})

    @property
    def groups(self) -> list[list[RunRow]]:
        """The runs of each POINT (building × configuration), in order of first appearance."""
        return list(point_groups(self.runs).values())

    @property
    def configs(self) -> dict[str, dict[str, float]]:
        """Configuration id → robot inputs, sorted by id."""
        return {m[0].config: dict(m[0].robot)
                for m in sorted(self.groups, key=lambda m: m[0].config)}

    @property
    def slam(self) -> str:
        """The runs' SLAM algorithm (one: :func:`read_runs` reads one)."""
        return self.runs[0].slam

    @property
    def max_urange_m(self) -> float | None:
        """GMapping's maxUrange of the runs, m (one value, checked by :func:`read_runs`)."""
        return self.runs[0].max_urange_m if self.runs else None

    @property
    def odom_model(self) -> str:
        """The runs' odometry model (one, checked by :func:`read_runs`; 'none' if all none)."""
        from slam_predict.learn.robot.records import common_odom_model

        return common_odom_model(self.runs) if self.runs else "none"

    @property
    def resolutions_deg(self) -> list[float]:
        """The distinct laser angular resolutions of the runs, deg, rounded to 0.01 deg
        (fov/0.5 + 1 beams, the count rounded, give 0.4997–0.5003 deg: all 0.5)."""
        return sorted({r.robot[RESOLUTION_INPUT] for r in self.runs})

    def feature_names(self) -> list[str]:
        """Every plan feature name of the table (its order), without the sight-line curve."""
        first = self.features[self.worlds[0]]
        return [k for k in first if k != "feature_version" and not k.startswith(COLUMN_PREFIX)]

    def sightline_curves(self) -> dict[str, list[float]]:
        """Building → its sight-line curve (features/sightline.py); InputError naming a
        building whose features lack it."""
        columns = curve_columns()
        for world in self.worlds:
            missing = [c for c in columns if c not in self.features[world]]
            if missing:
                raise InputError(f"the plan features of building '{world}' have no sight-line "
                                 f"curve ({missing[0]}...): compute the features with "
                                 "--worlds, or set sightline_input: false")
        return {w: [float(self.features[w][c]) for c in columns] for w in self.worlds}

    def input_value(self, world: str, robot: Mapping[str, float], name: str) -> float:
        """Input ``name`` of a point: a robot input, a derived input or a plan feature."""
        if name in ALL_ROBOT_INPUTS:
            return float(robot[name])
        if name in DERIVED_INPUTS:
            return derived_inputs(self.features[world], robot)[name]
        return float(self.features[world][name])

    def check_features(self, names: Sequence[str]) -> list[str]:
        """``names`` (all features when empty), checked: known and finite for every building."""
        known = self.feature_names()
        names = list(names) or known
        for name in names:
            if name not in known:
                hint = (" (a sight-line feature: compute the features with --worlds)"
                        if name in PLAN_COLUMNS else did_you_mean(name, known))
                raise InputError(f"plan feature '{name}' is not in the feature table" + hint)
            for world in self.worlds:
                if not math.isfinite(float(self.features[world].get(name, math.nan))):
                    raise InputError(f"plan feature '{name}' is missing for building '{world}'")
        return names

    def point_dataset(self, names: Sequence[str] = (),
                      robot: Sequence[str] = ROBOT_INPUTS) -> Dataset:
        """The POINT rows as the learning dataset: one row per building × configuration with
        its run count, four components, the robot inputs ``robot`` and the columns ``names``
        (plan features and derived inputs; default: every plan feature)."""
        names = list(names) or self.feature_names()
        groups = self.groups
        first = [m[0] for m in groups]
        targets = [point_targets(m) for m in groups]
        return Dataset(
            worlds=[r.world for r in first], feature_names=names,
            X=np.array([[self.input_value(r.world, r.robot, n) for n in names] for r in first],
                       dtype=float).reshape(len(first), len(names)),
            Y=np.array([[t[c] for c in COMPONENTS] for t in targets], dtype=float),
            runs=np.array([len(m) for m in groups], dtype=float),
            setting=[ROBOT_KIND] * len(first),
            slam_config_hash=[r.config_hashes.get(r.slam, "") for r in first],
            feature_version=[self.feature_version] * len(first),
            robot=[r.config for r in first], slam=[r.slam for r in first],
            robot_inputs={k: np.array([float(r.robot[k]) for r in first]) for k in robot})

    def tables_points(self, tables: RobotTables) -> Dataset:
        """The POINT rows with the columns of ``tables`` (plan features, derived and robot
        inputs): what a model folder's ``training_points.csv`` holds."""
        robot = [n for n in tables.names if n in ALL_ROBOT_INPUTS]
        return self.point_dataset([n for n in tables.names if n not in robot], robot)

    def config_tables(self, config) -> RobotTables:
        """:meth:`tables` with the inputs of a
        :class:`~slam_predict.learn.robot.config.RobotLearningConfig`."""
        return self.tables(config.plan_features, config.sightline_input, config.robot_inputs)

    def tables(self, plan_features: Sequence[str], derived: bool = False,
               robot: Sequence[str] = ROBOT_INPUTS) -> RobotTables:
        """The numeric tables over ``plan_features`` (checked) [+ DERIVED_INPUTS when
        ``derived``: the sight-line curves are checked] + the robot inputs ``robot``."""
        plan = self.check_features(plan_features)
        if derived:
            self.sightline_curves()
        names = plan + (list(DERIVED_INPUTS) if derived else []) + list(robot)
        points = self.point_dataset(names[:-len(robot)], robot)
        index = {m[0].point: i for i, m in enumerate(self.groups)}
        return RobotTables(
            names=names,
            run_X=np.array([[self.input_value(r.world, r.robot, n) for n in names]
                            for r in self.runs], dtype=float),
            run_y={k: np.array([getattr(r, k) for r in self.runs]) for k in RUN_TARGETS},
            run_point=np.array([index[r.point] for r in self.runs], dtype=int),
            point_X=points.columns(names),
            point_y={c: points.target(c) for c in COMPONENTS},
            point_runs=points.runs.astype(int),
            point_world=np.array(points.worlds),
            point_config=np.array(points.robot))

    def config_hashes(self) -> dict[str, list[str]]:
        """Component configuration (gmapping, sim, ...) → the distinct hashes of the runs."""
        out: dict[str, set[str]] = {}
        for run in self.runs:
            for key, value in run.config_hashes.items():
                out.setdefault(key, set()).add(value)
        return {k: sorted(v) for k, v in sorted(out.items())}


def build_run_data(runs: Sequence[RunRow], skipped: Mapping[str, int],
                   features: Mapping[str, Mapping[str, Any]], feature_version: str) -> RunData:
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
    return RunData(list(have), {w: dict(features[w]) for w in worlds}, feature_version,
                   skipped)


def learning_data(data_dirs: Sequence[os.PathLike | str], config, slam: str,
                  every_world: bool = False, **features: Any
                  ) -> tuple[RunData, dict[str, dict[str, float]], dict[str, Any]]:
    """(RunData, building → plan features, the full feature configuration) of the campaign
    folders' runs of SLAM algorithm ``slam`` under a RobotLearningConfig ``config``
    (min_coverage, max_urange_m), the plan features computed by :func:`plan_features` with
    ``features`` (``features_csv``, ``worlds_dir``, ``feature_config``, ``feature_version``,
    ``n_jobs``) for the buildings of the usable runs and, with ``every_world``, also of the
    runs that all failed (the failure model's inputs)."""
    from slam_predict.learn.robot.records import read_runs, record_worlds

    runs, skipped = read_runs(data_dirs, config.min_coverage, config.max_urange_m, slam)
    worlds = {r.world for r in runs} | (record_worlds(data_dirs, slam) if every_world else set())
    table, version, full_config = plan_features(sorted(worlds), **features)
    return build_run_data(runs, skipped, table, version), table, full_config


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


def runs_csv(data: RunData) -> str:
    """The RUN table as CSV (RUN_COLUMNS)."""
    return _csv(RUN_COLUMNS, [[r.world, r.run_index, r.seed, r.config, r.point, r.replicate,
                               *(r.robot[k] for k in ROBOT_INPUTS), r.coverage, r.trans_mean,
                               r.rot_mean] for r in data.runs])


# ----------------------------------------------------------------------------- plan features

def plan_features(worlds: Sequence[str], features_csv: os.PathLike | str | None = None,
                  worlds_dir: os.PathLike | str | None = None,
                  feature_config: Mapping[str, Any] | None = None,
                  feature_version: str | None = None,
                  n_jobs: int = 1) -> tuple[dict[str, dict[str, float]], str, dict[str, Any]]:
    """(building → features, feature version, full feature configuration) from a feature
    table (``learn dataset``'s format; version from its column or ``feature_version``) or
    computed on the plans in ``worlds_dir`` with ``feature_config`` (each plan loaded once; its
    sight-line curve columns, features/sightline.py, added)."""
    from slam_predict.learn.dataset import read_meta
    from slam_predict.learn.sources import read_feature_table

    if worlds_dir is not None:
        from slam_predict.features.plan import full_feature_config
        from slam_predict.features.sightline import sightline_features
        from slam_predict.learn.featurize import features_from_worlds

        config = full_feature_config(feature_config)
        features, version = features_from_worlds(worlds_dir, worlds, config, n_jobs,
                                                 also=sightline_features)
        return features, version, config
    if features_csv is None:
        raise InputError("give a feature table or a worlds folder")
    config = dict(read_meta(features_csv).get("feature_config") or {})
    table = read_feature_table(features_csv)
    versions = {str(v["feature_version"]) for v in table.values() if "feature_version" in v}
    if feature_version:
        versions = {feature_version}
    if len(versions) != 1 or not next(iter(versions)):
        raise InputError("features table needs one feature_version (column or "
                         "--feature-version)", features_csv)
    clean = {w: {k: v for k, v in vec.items() if k != "feature_version"}
             for w, vec in table.items()}
    return clean, versions.pop(), config
