"""Prepared scans for the real Karto SDK: the exact input of a Karto run as text, for the
differential check against slam_toolbox's karto_sdk (``bench/karto_diff/driver.cpp`` reads it,
``bench/bench_karto_diff.py`` writes it from the same input object our runner uses), and the
driver's JSON output.

Format (the ``backend karto`` variant of prepared scans version 1), one item per line::

    slam_predict_prepared_scans 1
    backend karto
    laser_pose x y theta             # laser in the base frame (m, rad)
    angles N a_0 ... a_N-1           # beam angles in the laser frame (rad), evenly spaced
    range_min r                      # m; shorter readings are ignored by Karto
    range_max r                      # m; the sensor's maximum range
    SCAN t x y theta r_0 ... r_N-1   # time (s), robot odometry pose (m, rad), ranges (m)

Numbers are written with ``repr`` so both sides see identical doubles. Karto's parameters are
not in this file: the driver takes slam_toolbox's YAML (or a flat JSON) beside it.
"""
from __future__ import annotations

import json
import os
from dataclasses import dataclass

import numpy as np

from slam_predict.atomic import write_text
from slam_predict.errors import InputError, require_file
from slam_predict.formats.prepared_scans import MAGIC, checked_scans

DRIVER_FORMAT = "karto_driver 1"
# evenly spaced beams: largest allowed deviation from the linear fit (rad)
SPACING_TOLERANCE = 1e-9


def sensor_range_max(laser, ranges) -> float:
    """The laser's maximum range (m), or the longest reading when the input does not say."""
    if np.isfinite(laser.range_max) and laser.range_max > 0:
        return float(laser.range_max)
    return float(np.nanmax(ranges))


def karto_scans_text(times, odometry, ranges, laser, range_min: float = 0.0) -> str:
    """The prepared-scans text of one Karto run; ``laser`` is a
    :class:`slam_predict.slam.LaserGeometry` whose beams must be evenly spaced (Karto describes a
    laser by its first angle and increment)."""
    times, odometry, ranges = checked_scans(times, odometry, ranges, laser)
    angles = laser.angles
    if laser.beams < 2:
        raise ValueError("Karto needs at least 2 beams")
    even = np.linspace(angles[0], angles[-1], laser.beams)
    if np.max(np.abs(angles - even)) > SPACING_TOLERANCE:
        raise ValueError("beam angles are not evenly spaced; Karto cannot describe this laser")
    lines = [MAGIC, "backend karto",
             "laser_pose " + " ".join(repr(float(v)) for v in laser.pose_in_base),
             f"angles {laser.beams} " + " ".join(repr(float(a)) for a in angles),
             f"range_min {float(range_min)!r}",
             f"range_max {sensor_range_max(laser, ranges)!r}"]
    for t, pose, row in zip(times.tolist(), odometry.tolist(), ranges.tolist(), strict=True):
        lines.append("SCAN " + " ".join(repr(v) for v in (t, *pose, *row)))
    return "\n".join(lines) + "\n"


def write_karto_scans(path: os.PathLike | str, times, odometry, ranges, laser,
                      range_min: float = 0.0) -> None:
    """Write :func:`karto_scans_text` to ``path`` (atomically)."""
    write_text(path, karto_scans_text(times, odometry, ranges, laser, range_min))


@dataclass
class KartoDriverOutput:
    """The driver's result: accepted scans' input indices (K,), stamps (K,) s and final corrected
    robot poses (K, 3) m/rad; loop closures (L, 2) as (closing scan, linked chain scan) input
    indices (−1: no new edge); CPU s of each Process call (M, 2) as (input index, s); timed
    occupancy-grid builds (dicts: after_input, accepted, cells, resolution, cpu_s)."""

    indices: np.ndarray
    stamps: np.ndarray
    poses: np.ndarray
    loop_closures: np.ndarray
    process_cpu: np.ndarray
    grid_cpu: list
    scans_in: int
    cpu_total_s: float


def read_karto_driver_output(path: os.PathLike | str) -> KartoDriverOutput:
    """Read the JSON the driver writes."""
    path = require_file(path, "Karto driver output")
    try:
        record = json.loads(open(path, encoding="utf-8").read())
        if record.get("format") != DRIVER_FORMAT:
            raise ValueError(f"format is {record.get('format')!r}, not {DRIVER_FORMAT!r}")
        table = np.array(record["accepted"], dtype=float).reshape(-1, 5)
        return KartoDriverOutput(
            table[:, 0].astype(np.int64), table[:, 1], table[:, 2:5],
            np.array(record["loop_closures"], dtype=np.int64).reshape(-1, 2),
            np.array(record["process_cpu_s"], dtype=float).reshape(-1, 2),
            list(record["grid_cpu"]), int(record["scans_in"]), float(record["cpu_total_s"]))
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise InputError(f"not a Karto driver output: {exc}", path) from None
