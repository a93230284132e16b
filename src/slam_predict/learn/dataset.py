"""Learning dataset: per-building error statistics joined with feature vectors, with provenance.

One row per building and robot configuration: ``world``, ``robot`` (the robot configuration hash
of the collection summary, :func:`slam_predict.sensor.sensor_hash`; empty for the thesis tables
and older summaries), provenance (``setting``, ``slam_config_hash``, ``feature_version``,
``runs``), the four targets (``trans_mean``, ``trans_std`` in m; ``rot_mean``, ``rot_std`` in
rad), optional reference columns (``ref_*``: numbers known only from the source table, e.g. the
thesis' own Voronoi distance; never used as features) and the features.

Error statistics come from the collection summary (``world, runs, trans_mean, …``) or from the
seed thesis' tables (``dataset, Voronoi distance, …, transError.mean.mean, …``; header names
after the first carry a leading space).
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

import numpy as np

from slam_predict.atomic import write_text
from slam_predict.errors import InputError, did_you_mean, require_file

LOG = logging.getLogger(__name__)

COMPONENTS = ("trans_mean", "trans_std", "rot_mean", "rot_std")
UNITS = {"trans_mean": "m", "trans_std": "m", "rot_mean": "rad", "rot_std": "rad"}
PROVENANCE = ("setting", "slam_config_hash", "feature_version", "runs")
REF_PREFIX = "ref_"
THESIS_TARGETS = {"transError.mean.mean": "trans_mean", "transError.mean.std": "trans_std",
                  "rotError.mean.mean": "rot_mean", "rotError.mean.std": "rot_std"}
THESIS_REFERENCE = {"Voronoi distance": "ref_voronoi_distance",
                    "Voronoi rotation": "ref_voronoi_rotation",
                    "totalLen": "ref_total_len", "totalRot": "ref_total_rot"}
SUMMARY_REFERENCE = {"path_length_mean": "ref_total_len", "rotation_mean": "ref_total_rot"}
THESIS_SLAM = "thesis-gmapping"  # slam_config_hash of rows taken from the thesis tables


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


@dataclass
class Dataset:
    """Buildings × (features, targets) with per-row provenance.

    Attributes:
        worlds: building names, one per row.
        feature_names: column names of ``X``.
        X: (n, F) feature matrix.
        Y: (n, 4) targets in the order of COMPONENTS.
        runs: (n,) number of runs per building (NaN when unknown).
        setting, slam_config_hash, feature_version: per-row provenance strings.
        reference: name → (n,) reference columns (never features).
        robot: (n,) robot configuration hashes ('' = unknown); None = all unknown.
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

    def __post_init__(self) -> None:
        if self.robot is None:
            self.robot = [""] * len(self.worlds)

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
                       {k: v[rows] for k, v in self.reference.items()}, pick(self.robot))

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


def component_index(component: str) -> int:
    """Column of ``component`` in Y; InputError with a hint when unknown."""
    if component not in COMPONENTS:
        raise InputError(f"unknown component '{component}' (choose from {', '.join(COMPONENTS)})"
                         + did_you_mean(component, COMPONENTS))
    return COMPONENTS.index(component)


# ----------------------------------------------------------------------------- reading tables

def _read_csv(path: str) -> list[dict[str, str]]:
    """Rows of a CSV file as dicts with stripped header names and values."""
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


def _number(row: Mapping[str, str], column: str, path: str, allow_empty: bool = False) -> float:
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


def _require_columns(rows: list[dict[str, str]], needed: Sequence[str], path: str) -> None:
    have = [c for c in rows[0] if c != "__line__"]
    for column in needed:
        if column not in have:
            raise InputError(f"missing column '{column}'" + did_you_mean(column, have), path)


def read_error_table(path: os.PathLike | str, setting: str = "") -> list[ErrorRow]:
    """Per-building error statistics from a collection summary or a thesis stats table.

    ``setting`` fills rows whose table has no ``setting`` column (the thesis tables).
    """
    path = os.fspath(path)
    rows = _read_csv(path)
    if "dataset" in rows[0] and "transError.mean.mean" in rows[0]:
        result = _thesis_rows(rows, path, setting)
    else:
        result = _summary_rows(rows, path, setting)
    seen = set()
    for row in result:
        if (row.world, row.robot) in seen:
            robot = f" with robot {row.robot}" if row.robot else ""
            raise InputError(f"building '{row.world}'{robot} appears twice", path)
        seen.add((row.world, row.robot))
    return result


def _thesis_rows(rows, path: str, setting: str) -> list[ErrorRow]:
    _require_columns(rows, ["dataset", *THESIS_TARGETS], path)
    out = []
    for row in rows:
        targets = {name: _number(row, col, path) for col, name in THESIS_TARGETS.items()}
        reference = {name: _number(row, col, path) for col, name in THESIS_REFERENCE.items()
                     if col in row}
        out.append(ErrorRow(row["dataset"], targets, math.nan, setting, THESIS_SLAM, reference))
    return out


def _summary_rows(rows, path: str, setting: str) -> list[ErrorRow]:
    _require_columns(rows, ["world", *COMPONENTS], path)
    hash_column = next((c for c in ("slam_config_hash", "config_hash") if c in rows[0]), None)
    out = []
    for row in rows:
        targets = {name: _number(row, name, path) for name in COMPONENTS}
        runs = _number(row, "runs", path, allow_empty=True) if "runs" in row else math.nan
        reference = {name: _number(row, col, path, allow_empty=True)
                     for col, name in SUMMARY_REFERENCE.items() if col in row}
        out.append(ErrorRow(row["world"], targets, runs, row.get("setting") or setting,
                            row[hash_column] if hash_column else "", reference,
                            row.get("robot") or ""))
    return out


def read_feature_table(path: os.PathLike | str) -> dict[str, dict[str, float]]:
    """World → {feature: value} from a CSV with a ``world`` column and numeric features.

    A ``feature_version`` column, if present, is kept as the pseudo-feature of that name (str).
    """
    path = os.fspath(path)
    rows = _read_csv(path)
    _require_columns(rows, ["world"], path)
    skip = {"world", "__line__", "feature_version"}
    out: dict[str, dict[str, float]] = {}
    for row in rows:
        values = {c: _number(row, c, path, allow_empty=True) for c in row if c not in skip}
        if "feature_version" in row:
            values["feature_version"] = row["feature_version"]  # type: ignore[assignment]
        out[row["world"]] = values
    return out


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
    by_norm = {_normalise(name): name for name in features}
    matched = []
    for row in errors:
        key = row.world if row.world in features else by_norm.get(_normalise(row.world))
        if key is None:
            continue
        matched.append((row, features[key]))
    dropped = len(errors) - len(matched)
    if dropped:
        LOG.info("%d of %d buildings have no feature vector and are left out", dropped,
                 len(errors))
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
        robot=[row.robot for row, _ in matched])


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
                   ["reference-table"] * len(data), dict(data.reference), list(data.robot))


# ----------------------------------------------------------------------------- CSV round trip

def to_csv_text(data: Dataset) -> str:
    """The dataset as CSV text (provenance, targets, ``ref_*`` columns, then features)."""
    refs = sorted(data.reference)
    header = ["world", "robot", *PROVENANCE, *COMPONENTS, *refs, *data.feature_names]
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(header)
    for i, world in enumerate(data.worlds):
        runs = "" if math.isnan(data.runs[i]) else f"{data.runs[i]:g}"
        writer.writerow([world, data.robot[i], data.setting[i], data.slam_config_hash[i],
                         data.feature_version[i], runs,
                         *(repr(float(v)) for v in data.Y[i]),
                         *(repr(float(data.reference[r][i])) for r in refs),
                         *(repr(float(v)) for v in data.X[i])])
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


def write_feature_table(features: Mapping[str, Mapping[str, float]], version: str,
                        path: os.PathLike | str,
                        meta: Mapping[str, object] | None = None) -> None:
    """Write {world: {feature: value}} as a CSV (world, feature_version, features...)."""
    names = list(next(iter(features.values())))
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["world", "feature_version", *names])
    for world, vector in features.items():
        writer.writerow([world, version, *(repr(float(vector[n])) for n in names)])
    if meta is not None:
        write_text(meta_path(path), json.dumps(dict(meta), indent=2, default=str) + "\n")
    write_text(path, out.getvalue())


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
    """Read a dataset CSV written by :func:`write_dataset`."""
    path = os.fspath(path)
    rows = _read_csv(path)
    _require_columns(rows, ["world", *PROVENANCE, *COMPONENTS], path)
    fixed = {"world", "robot", "__line__", *PROVENANCE, *COMPONENTS}
    refs = [c for c in rows[0] if c.startswith(REF_PREFIX)]
    names = [c for c in rows[0] if c not in fixed and c not in refs]
    if not names:
        raise InputError("dataset has no feature columns", path)
    return Dataset(
        worlds=[r["world"] for r in rows], feature_names=names,
        X=np.array([[_number(r, n, path, allow_empty=True) for n in names] for r in rows]),
        Y=np.array([[_number(r, c, path) for c in COMPONENTS] for r in rows]),
        runs=np.array([_number(r, "runs", path, allow_empty=True) for r in rows]),
        setting=[r["setting"] for r in rows],
        slam_config_hash=[r["slam_config_hash"] for r in rows],
        feature_version=[r["feature_version"] for r in rows],
        reference={c: np.array([_number(r, c, path, allow_empty=True) for r in rows])
                   for c in refs},
        robot=[r.get("robot") or "" for r in rows])
