"""TUM trajectory files: one pose per line, ``timestamp x y z qx qy qz qw`` (s, m, unit quaternion).

Planar poses (x m, y m, yaw rad) are written with z = 0 and a yaw-only quaternion, every number
in full double precision, so a write/read round trip is exact up to the yaw ↔ quaternion
conversion (~1e-16 rad). Reading projects any 3D pose onto the plane (yaw of the quaternion).
``#`` comment lines and blank lines are skipped. A truncated last line (fewer than 8 fields, or an
unterminated line that does not parse) is dropped with a warning (the thesis' adjustment); any
other line that is not 8 numbers is an error.
"""
from __future__ import annotations

import logging
import os
import warnings
from collections.abc import Iterable, Sequence

import numpy as np

from slam_predict.atomic import write_text
from slam_predict.errors import InputError, require_file
from slam_predict.formats.text_rows import parse_number_row
from slam_predict.geometry import quaternion_to_yaw, wrap_angle, yaw_to_quaternion

log = logging.getLogger(__name__)


def tum_lines(t: Sequence[float], poses: np.ndarray) -> list:
    """The TUM lines (no newlines) for times ``t`` (N,) s and planar ``poses`` (N, 3)."""
    t = np.asarray(t, dtype=float).reshape(-1)
    poses = np.asarray(poses, dtype=float).reshape(-1, 3)
    if len(t) != len(poses):
        raise ValueError(f"length mismatch: {len(t)} timestamps, {len(poses)} poses")
    quats = yaw_to_quaternion(poses[:, 2]).reshape(-1, 4)
    out = []
    for ti, (x, y, _), q in zip(t.tolist(), poses.tolist(), quats.tolist(), strict=False):
        out.append(" ".join(repr(float(v)) for v in (ti, x, y, 0.0, *q)))
    return out


def write_tum(path: os.PathLike | str, t: Sequence[float], poses: np.ndarray,
              header: Iterable[str] = ()) -> None:
    """Write a planar trajectory as a TUM file, atomically (``header`` → ``#`` comment lines)."""
    lines = [f"# {h}" for h in header] + tum_lines(t, poses)
    write_text(path, "\n".join(lines) + ("\n" if lines else ""))


def read_tum(path: os.PathLike | str, return_z: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Read a TUM file → (t (N,) s, poses (N, 3) as x, y, yaw).

    ``return_z=True`` returns ``(t, poses, z)`` with the z column too (m), for callers that
    want to check a trajectory really is planar.
    """
    path = require_file(path, "TUM trajectory")
    data = _fast_load(path)
    if data is None:           # some line is unusual or bad: parse line by line to say which
        data = _careful_load(path)
    norms = np.linalg.norm(data[:, 4:8], axis=1)
    bad = np.flatnonzero(np.abs(norms - 1.0) > 1e-3)
    if len(bad):
        raise InputError(f"quaternion norm {norms[bad[0]]:.4g} is not 1 (pose {bad[0] + 1})", path)
    yaw = wrap_angle(quaternion_to_yaw(data[:, 4], data[:, 5], data[:, 6], data[:, 7]))
    poses = np.column_stack([data[:, 1], data[:, 2], yaw])
    if return_z:
        return data[:, 0], poses, data[:, 3]
    return data[:, 0], poses


def _fast_load(path: str):
    """All rows via numpy's C parser, or None when the file is not plain 8-column numbers."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")          # empty-file warning
            data = np.loadtxt(path, comments="#", ndmin=2, dtype=float)
    except (ValueError, OSError, UnicodeDecodeError):
        return None
    if data.size == 0:
        return np.zeros((0, 8))
    if data.shape[1] != 8 or not np.all(np.isfinite(data)):
        return None
    return data


def _careful_load(path: str) -> np.ndarray:
    try:
        with open(path, encoding="utf-8") as fh:
            lines = fh.readlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read TUM trajectory: {exc}", path) from None
    last = max((i for i, ln in enumerate(lines, start=1) if ln.strip()), default=0)
    rows = []
    for number, line in enumerate(lines, start=1):
        text = line.strip()
        if not text or text.startswith("#"):
            continue
        try:
            rows.append(_parse_row(text, path, number))
        except InputError:
            if number == last and (len(text.split()) < 8 or not line.endswith("\n")):
                log.warning("%s:%d: dropping truncated last line", path, number)
                continue
            raise
    return np.array(rows, dtype=float).reshape(-1, 8)


def _parse_row(text: str, path: str, number: int) -> list:
    return parse_number_row(text.replace(",", " ").split(), "timestamp x y z qx qy qz qw",
                            "TUM line", path, number)
