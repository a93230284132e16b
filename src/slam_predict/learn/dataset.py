"""The learning dataset: one row per building (and robot configuration), the ONE format both
model families are built from and read back.

Columns: ``world``; ``robot`` (the robot configuration's key: the hash of the collection
summary, :func:`slam_predict.sensor.sensor_hash`, or a design configuration id; empty for the
thesis tables and older summaries); ``slam`` (optional: the SLAM algorithm of the row's runs,
one of :data:`~slam_predict.learn.card.SLAM_ALGORITHMS`; written only when a row is not
``gmapping``, absent = gmapping); provenance (``setting``, ``slam_config_hash``,
``feature_version``, ``runs``); the four targets (``trans_mean``, ``trans_std`` in m;
``rot_mean``, ``rot_std`` in rad; a std is empty for a row of one run); reference columns
(``ref_*``: numbers known only from the source table, e.g. the thesis' own Voronoi distance;
never used as features); optional robot
columns (:data:`~slam_predict.learn.robot.inputs.ALL_ROBOT_INPUTS`, in their units) and the
features. A plan-only dataset has no robot columns; the robot-aware models' POINT rows (one per
building × robot configuration, :mod:`slam_predict.learn.robot.rundata`) have them.

Old files stay readable: a robot-aware model folder's ``training_points.csv`` written before
this format (columns ``world, config, point, runs``, robot inputs, targets, features: ``config``
is the robot key, ``point`` is dropped, provenance empty). The tables a dataset is built from
are read by :mod:`slam_predict.learn.sources`.
"""
from __future__ import annotations

import csv
import io
import json
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from slam_predict.atomic import write_text
from slam_predict.errors import InputError, did_you_mean, require_file
from slam_predict.learn.card import DEFAULT_SLAM, check_slam
from slam_predict.learn.robot.inputs import ALL_ROBOT_INPUTS

COMPONENTS = ("trans_mean", "trans_std", "rot_mean", "rot_std")
UNITS = {"trans_mean": "m", "trans_std": "m", "rot_mean": "rad", "rot_std": "rad"}
PROVENANCE = ("setting", "slam_config_hash", "feature_version", "runs")
STD_COMPONENTS = ("trans_std", "rot_std")   # may be empty in a file: NaN for one run
REF_PREFIX = "ref_"
LEGACY_POINT_COLUMNS = ("config", "point")   # robot key and point id of old POINT files


@dataclass
class ErrorRow:
    """Measured error statistics of one building (targets in m and rad)."""

    world: str
    targets: dict[str, float]
    runs: float = math.nan
    setting: str = ""
    slam_config_hash: str = ""
    reference: dict[str, float] = field(default_factory=dict)
    robot: str = ""
    slam: str = DEFAULT_SLAM


@dataclass
class Dataset:
    """Buildings (× robot configurations) × (features, targets) with per-row provenance.

    Attributes:
        worlds: building names, one per row.
        feature_names: column names of ``X``.
        X: (n, F) feature matrix.
        Y: (n, 4) targets in the order of COMPONENTS.
        runs: (n,) number of runs per row (NaN when unknown).
        setting, slam_config_hash, feature_version: per-row provenance strings.
        reference: name → (n,) reference columns (never features).
        robot: (n,) robot configuration keys ('' = unknown); None = all unknown.
        slam: (n,) SLAM algorithm of each row's runs; None = all gmapping.
        robot_inputs: robot input → (n,) values in its unit; empty for a plan-only dataset.
    """

    worlds: list[str]
    feature_names: list[str]
    X: np.ndarray
    Y: np.ndarray
    runs: np.ndarray
    setting: list[str]
    slam_config_hash: list[str]
    feature_version: list[str]
    reference: dict[str, np.ndarray] = field(default_factory=dict)
    robot: list[str] | None = None
    slam: list[str] | None = None
    robot_inputs: dict[str, np.ndarray] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.robot is None:
            self.robot = [""] * len(self.worlds)
        if self.slam is None:
            self.slam = [DEFAULT_SLAM] * len(self.worlds)

    def __len__(self) -> int:
        return len(self.worlds)

    def target(self, component: str) -> np.ndarray:
        """The (n,) target column of ``component``."""
        return self.Y[:, component_index(component)]

    def subset(self, rows: Sequence[int]) -> Dataset:
        """The dataset restricted to ``rows`` (indices)."""
        rows = np.asarray(rows, dtype=int)
        pick = lambda values: [values[i] for i in rows]  # noqa: E731
        return Dataset(pick(self.worlds), list(self.feature_names), self.X[rows], self.Y[rows],
                       self.runs[rows], pick(self.setting), pick(self.slam_config_hash),
                       pick(self.feature_version),
                       {k: v[rows] for k, v in self.reference.items()}, pick(self.robot),
                       pick(self.slam), {k: v[rows] for k, v in self.robot_inputs.items()})

    def unique(self, attribute: str) -> str:
        """The single value of a provenance column; InputError when rows disagree."""
        values = sorted(set(getattr(self, attribute)))
        if len(values) != 1:
            raise InputError(f"dataset mixes several values of {attribute}: {', '.join(values)}")
        return values[0]

    def feature_ranges(self) -> dict[str, list[float]]:
        """Feature name → [min, max] over the buildings."""
        return {name: [float(np.nanmin(self.X[:, j])), float(np.nanmax(self.X[:, j]))]
                for j, name in enumerate(self.feature_names)}

    def columns(self, names: Sequence[str]) -> np.ndarray:
        """The (n, len(names)) columns ``names``, each a feature or a robot input."""
        out = []
        for name in names:
            if name in self.robot_inputs:
                out.append(self.robot_inputs[name])
            elif name in self.feature_names:
                out.append(self.X[:, self.feature_names.index(name)])
            else:
                raise InputError(f"dataset has no column '{name}'"
                                 + did_you_mean(name, [*self.feature_names, *self.robot_inputs]))
        return np.column_stack(out) if out else np.zeros((len(self), 0))

    def select_slam(self, slam: str = DEFAULT_SLAM) -> Dataset:
        """The rows of SLAM algorithm ``slam``; InputError naming the algorithms present when
        none is."""
        check_slam(slam)
        rows = [i for i, name in enumerate(self.slam) if name == slam]
        if not rows:
            present = ", ".join(sorted(set(self.slam)))
            raise InputError(f"the dataset has no rows of SLAM algorithm '{slam}' (it holds "
                             f"{present}): give --slam NAME")
        return self if len(rows) == len(self) else self.subset(rows)


def component_index(component: str) -> int:
    """Column of ``component`` in Y; InputError with a hint when unknown."""
    if component not in COMPONENTS:
        raise InputError(f"unknown component '{component}' (choose from {', '.join(COMPONENTS)})"
                         + did_you_mean(component, COMPONENTS))
    return COMPONENTS.index(component)


# ----------------------------------------------------------------------------- CSV cells

def read_csv_rows(path: str) -> list[dict[str, str]]:
    """Rows of a CSV file as dicts with stripped header names and values (+ ``__line__``)."""
    require_file(path, "table")
    with open(path, newline="", encoding="utf-8") as handle:
        reader = csv.reader(handle)
        try:
            header = [h.strip() for h in next(reader)]
        except StopIteration:
            raise InputError("empty table", path) from None
        rows = []
        for line, values in enumerate(reader, start=2):
            if not values or all(not v.strip() for v in values):
                continue
            if len(values) != len(header):
                raise InputError(f"{len(values)} fields, header has {len(header)}", path, line)
            row = {h: v.strip() for h, v in zip(header, values, strict=False)}
            row["__line__"] = str(line)
            rows.append(row)
    if not rows:
        raise InputError("table has no data rows", path)
    return rows


def number(row: Mapping[str, str], column: str, path: str, allow_empty: bool = False) -> float:
    """The number in ``column`` of a row of :func:`read_csv_rows`; InputError naming the line
    when it is not one (empty → NaN when ``allow_empty``, else non-finite is refused)."""
    text = row[column]
    if text == "" and allow_empty:
        return math.nan
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"column '{column}' is not a number: {text!r}", path,
                         int(row["__line__"])) from None
    if not allow_empty and not math.isfinite(value):
        raise InputError(f"column '{column}' is not finite: {text!r}", path, int(row["__line__"]))
    return value


def require_columns(rows: list[dict[str, str]], needed: Sequence[str], path: str) -> None:
    """InputError (with a hint) naming the first column of ``needed`` the table lacks."""
    have = [c for c in rows[0] if c != "__line__"]
    for column in needed:
        if column not in have:
            raise InputError(f"missing column '{column}'" + did_you_mean(column, have), path)


# ----------------------------------------------------------------------------- joining

def _normalise(name: str) -> str:
    """Lower case without ``_``, ``-``, spaces and an ``_updated`` suffix (thesis names)."""
    name = name.lower()
    if name.endswith("_updated"):
        name = name[: -len("_updated")]
    return "".join(ch for ch in name if ch not in "_- ")


def join(errors: Sequence[ErrorRow], features: Mapping[str, Mapping[str, float]],
         feature_version: str, setting: str = "") -> Dataset:
    """Join error rows with feature vectors by building name (exact, then normalised match).

    Buildings without features are dropped (logged); features must have the same names for
    every building. ``setting`` overrides empty per-row settings.
    """
    import logging

    by_norm = {_normalise(name): name for name in features}
    matched = []
    for row in errors:
        key = row.world if row.world in features else by_norm.get(_normalise(row.world))
        if key is None:
            continue
        matched.append((row, features[key]))
    dropped = len(errors) - len(matched)
    if dropped:
        logging.getLogger(__name__).info("%d of %d buildings have no feature vector and are "
                                         "left out", dropped, len(errors))
    if len(matched) < 2:
        raise InputError(f"only {len(matched)} buildings have both errors and features")
    names = [k for k in matched[0][1] if k != "feature_version"]
    for row, vector in matched:
        if sorted(k for k in vector if k != "feature_version") != sorted(names):
            raise InputError(f"building '{row.world}' has a different feature set")
    versions = [str(vector.get("feature_version", feature_version)) for _, vector in matched]
    refs = sorted({k for row, _ in matched for k in row.reference})
    return Dataset(
        worlds=[row.world for row, _ in matched], feature_names=names,
        X=np.array([[float(vector[n]) for n in names] for _, vector in matched], dtype=float),
        Y=np.array([[row.targets[c] for c in COMPONENTS] for row, _ in matched], dtype=float),
        runs=np.array([row.runs for row, _ in matched], dtype=float),
        setting=[row.setting or setting for row, _ in matched],
        slam_config_hash=[row.slam_config_hash for row, _ in matched],
        feature_version=versions,
        reference={k: np.array([row.reference.get(k, math.nan) for row, _ in matched])
                   for k in refs},
        robot=[row.robot for row, _ in matched], slam=[row.slam for row, _ in matched])


def reference_as_features(data: Dataset, columns: Sequence[str]) -> Dataset:
    """A copy whose features are reference columns (development and tests only).

    Marks ``feature_version`` as ``reference-table``, which no shipped model may use.
    """
    missing = [c for c in columns if c not in data.reference]
    if missing:
        raise InputError(f"dataset has no reference column {missing[0]}"
                         + did_you_mean(missing[0], data.reference))
    X = np.column_stack([data.reference[c] for c in columns])
    return Dataset(list(data.worlds), [c[len(REF_PREFIX):] for c in columns], X, data.Y.copy(),
                   data.runs.copy(), list(data.setting), list(data.slam_config_hash),
                   ["reference-table"] * len(data), dict(data.reference), list(data.robot),
                   list(data.slam), dict(data.robot_inputs))


# ----------------------------------------------------------------------------- CSV round trip

def _cell(value: float) -> str:
    return repr(float(value))


def _target_cell(value: float) -> str:
    """A target: empty for NaN (the std of a POINT row of one run)."""
    return "" if math.isnan(value) else repr(float(value))


def to_csv_text(data: Dataset) -> str:
    """The dataset as CSV text (keys, provenance, targets, ``ref_*``, robot inputs, features);
    the ``slam`` column only when a row is not gmapping."""
    refs = sorted(data.reference)
    inputs = list(data.robot_inputs)
    with_slam = any(name != DEFAULT_SLAM for name in data.slam)
    header = ["world", "robot", *(["slam"] if with_slam else []), *PROVENANCE, *COMPONENTS,
              *refs, *inputs, *data.feature_names]
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(header)
    for i, world in enumerate(data.worlds):
        runs = "" if math.isnan(data.runs[i]) else f"{data.runs[i]:g}"
        writer.writerow([world, data.robot[i], *([data.slam[i]] if with_slam else []),
                         data.setting[i], data.slam_config_hash[i], data.feature_version[i],
                         runs, *(_target_cell(v) for v in data.Y[i]),
                         *(_cell(data.reference[r][i]) for r in refs),
                         *(_cell(data.robot_inputs[k][i]) for k in inputs),
                         *(_cell(v) for v in data.X[i])])
    return out.getvalue()


def meta_path(path: os.PathLike | str) -> str:
    """The JSON sidecar of a dataset CSV (feature configuration, sources)."""
    return os.path.splitext(os.fspath(path))[0] + ".json"


def write_dataset(data: Dataset, path: os.PathLike | str,
                  meta: Mapping[str, object] | None = None) -> None:
    """Write the dataset CSV (and its JSON sidecar when ``meta`` is given) atomically."""
    if meta is not None:
        write_text(meta_path(path), json.dumps(dict(meta), indent=2, default=str) + "\n")
    write_text(path, to_csv_text(data))


def read_meta(path: os.PathLike | str) -> dict[str, object]:
    """The sidecar of a dataset CSV ({} when absent); InputError when unreadable."""
    side = meta_path(path)
    if not os.path.isfile(side):
        return {}
    try:
        meta = json.loads(open(side, encoding="utf-8").read())
    except (OSError, ValueError) as exc:
        raise InputError(f"unreadable dataset sidecar ({exc.__class__.__name__})", side) from None
    return meta if isinstance(meta, dict) else {}


def read_dataset(path: os.PathLike | str) -> Dataset:
    """Read a dataset CSV written by :func:`write_dataset` (or an old POINT file, module
    doc)."""
    path = os.fspath(path)
    rows = read_csv_rows(path)
    legacy = "config" in rows[0] and "robot" not in rows[0]
    robot_key = "config" if legacy else "robot"
    strings = () if legacy else PROVENANCE[:3]
    require_columns(rows, ["world", *strings, "runs", *COMPONENTS], path)
    fixed = {"world", "robot", "slam", "__line__", *PROVENANCE, *COMPONENTS,
             *(LEGACY_POINT_COLUMNS if legacy else ())}
    refs = [c for c in rows[0] if c.startswith(REF_PREFIX)]
    inputs = [c for c in ALL_ROBOT_INPUTS if c in rows[0]]
    names = [c for c in rows[0] if c not in fixed and c not in refs and c not in inputs]
    if not names:
        raise InputError("dataset has no feature columns", path)
    slams = [r.get("slam") or DEFAULT_SLAM for r in rows]
    for row, slam in zip(rows, slams, strict=True):
        _check_slam_cell(slam, path, row)
    text = lambda column: [r.get(column, "") for r in rows]  # noqa: E731
    return Dataset(
        worlds=text("world"), feature_names=names,
        X=np.array([[number(r, n, path, allow_empty=True) for n in names] for r in rows]),
        Y=np.array([[number(r, c, path, allow_empty=c in STD_COMPONENTS) for c in COMPONENTS]
                    for r in rows]),
        runs=np.array([number(r, "runs", path, allow_empty=True) for r in rows]),
        setting=text("setting"), slam_config_hash=text("slam_config_hash"),
        feature_version=text("feature_version"),
        reference={c: np.array([number(r, c, path, allow_empty=True) for r in rows])
                   for c in refs},
        robot=text(robot_key), slam=slams,
        robot_inputs={c: np.array([number(r, c, path) for r in rows]) for c in inputs})


def _check_slam_cell(slam: str, path: str, row: Mapping[str, str]) -> None:
    try:
        check_slam(slam)
    except InputError as exc:
        raise InputError(exc.problem, path, int(row["__line__"])) from None
