"""The tables a learning dataset (:mod:`slam_predict.learn.dataset`) is built from: per-building
error statistics and feature tables.

Error statistics come from a collection summary (``world, runs, trans_mean, …``; optional
``robot`` and ``slam`` columns) or from the seed thesis' tables (``dataset, Voronoi distance,
…, transError.mean.mean, …``; header names after the first carry a leading space; every row is
GMapping's). A summary without a ``slam`` column takes each building's SLAM algorithm from the
run records beside it (``<world>/run_NNN/run.json``, ``slam.type``: the campaign's settings,
``slam.type`` of collect.yaml), gmapping when they name none or are absent.
"""
from __future__ import annotations

import csv
import io
import json
import logging
import math
import os
from collections.abc import Mapping
from pathlib import Path

from slam_predict.atomic import write_text
from slam_predict.errors import InputError
from slam_predict.learn.card import DEFAULT_SLAM, check_slam
from slam_predict.learn.dataset import (
    COMPONENTS,
    ErrorRow,
    meta_path,
    number,
    read_csv_rows,
    require_columns,
)

LOG = logging.getLogger(__name__)
THESIS_TARGETS = {"transError.mean.mean": "trans_mean", "transError.mean.std": "trans_std",
                  "rotError.mean.mean": "rot_mean", "rotError.mean.std": "rot_std"}
THESIS_REFERENCE = {"Voronoi distance": "ref_voronoi_distance",
                    "Voronoi rotation": "ref_voronoi_rotation",
                    "totalLen": "ref_total_len", "totalRot": "ref_total_rot"}
SUMMARY_REFERENCE = {"path_length_mean": "ref_total_len", "rotation_mean": "ref_total_rot"}
THESIS_SLAM = "thesis-gmapping"  # slam_config_hash of rows taken from the thesis tables


def read_error_table(path: os.PathLike | str, setting: str = "") -> list[ErrorRow]:
    """Per-building error statistics from a collection summary or a thesis stats table.

    ``setting`` fills rows whose table has no ``setting`` column (the thesis tables).
    """
    path = os.fspath(path)
    rows = read_csv_rows(path)
    if "dataset" in rows[0] and "transError.mean.mean" in rows[0]:
        result = _thesis_rows(rows, path, setting)
    else:
        result = _summary_rows(rows, path, setting)
    seen = set()
    for row in result:
        key = (row.world, row.robot, row.slam)
        if key in seen:
            robot = f" with robot {row.robot}" if row.robot else ""
            raise InputError(f"building '{row.world}'{robot} appears twice", path)
        seen.add(key)
    return result


def _thesis_rows(rows, path: str, setting: str) -> list[ErrorRow]:
    require_columns(rows, ["dataset", *THESIS_TARGETS], path)
    out = []
    for row in rows:
        targets = {name: number(row, col, path) for col, name in THESIS_TARGETS.items()}
        reference = {name: number(row, col, path) for col, name in THESIS_REFERENCE.items()
                     if col in row}
        out.append(ErrorRow(row["dataset"], targets, math.nan, setting, THESIS_SLAM, reference))
    return out


def _summary_rows(rows, path: str, setting: str) -> list[ErrorRow]:
    require_columns(rows, ["world", *COMPONENTS], path)
    hash_column = next((c for c in ("slam_config_hash", "config_hash") if c in rows[0]), None)
    slams = None if "slam" in rows[0] else RunSlams(Path(path).parent)
    out = []
    for row in rows:
        targets = {name: number(row, name, path) for name in COMPONENTS}
        runs = number(row, "runs", path, allow_empty=True) if "runs" in row else math.nan
        reference = {name: number(row, col, path, allow_empty=True)
                     for col, name in SUMMARY_REFERENCE.items() if col in row}
        slam = (row["slam"] or DEFAULT_SLAM) if slams is None else slams.of_world(row["world"])
        try:
            check_slam(slam)
        except InputError as exc:
            raise InputError(exc.problem, path, int(row["__line__"])) from None
        out.append(ErrorRow(row["world"], targets, runs, row.get("setting") or setting,
                            row[hash_column] if hash_column else "", reference,
                            row.get("robot") or "", slam))
    return out


class RunSlams:
    """The SLAM algorithm of each building's run records in a campaign folder (module doc)."""

    def __init__(self, folder: Path):
        self.folder = folder

    def of_world(self, world: str) -> str:
        """The one algorithm of ``world``'s runs (gmapping without runs or names);
        InputError naming two runs of different algorithms."""
        found: dict[str, Path] = {}
        for path in sorted(self.folder.glob(f"{world}/run_*/run.json")):
            found.setdefault(_slam_of(path), path)
        if len(found) > 1:
            (first, a), (second, b) = list(found.items())[:2]
            raise InputError(f"building '{world}' has runs of two SLAM algorithms ({first} in "
                             f"{a}, {second} here): collect them in separate campaigns", b)
        return next(iter(found), DEFAULT_SLAM)


def _slam_of(path: Path) -> str:
    """``slam.type`` of a run.json (gmapping when it has none)."""
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise InputError(f"unreadable run record ({exc.__class__.__name__})", path) from None
    slam = record.get("slam") if isinstance(record, dict) else None
    return str(slam.get("type") or DEFAULT_SLAM) if isinstance(slam, dict) else DEFAULT_SLAM


def read_feature_table(path: os.PathLike | str) -> dict[str, dict[str, float]]:
    """World → {feature: value} from a CSV with a ``world`` column and numeric features.

    A ``feature_version`` column, if present, is kept as the pseudo-feature of that name (str).
    """
    path = os.fspath(path)
    rows = read_csv_rows(path)
    require_columns(rows, ["world"], path)
    skip = {"world", "__line__", "feature_version"}
    out: dict[str, dict[str, float]] = {}
    for row in rows:
        values = {c: number(row, c, path, allow_empty=True) for c in row if c not in skip}
        if "feature_version" in row:
            values["feature_version"] = row["feature_version"]  # type: ignore[assignment]
        out[row["world"]] = values
    return out


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
