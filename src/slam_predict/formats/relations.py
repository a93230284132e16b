"""Freiburg relations files (Kümmerle et al. 2009, read by metricEvaluator).

One relation per line: ``timestamp1 timestamp2 x y z roll pitch yaw`` — the displacement from the
pose at timestamp1 to the pose at timestamp2 expressed in the first pose's frame (m, rad). ``#``
starts a comment line. For planar data z, roll and pitch are 0; a non-zero value is logged as a
warning and ignored (only x, y, yaw are used).
"""
from __future__ import annotations

import logging
import os
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from slam_predict.atomic import write_text
from slam_predict.errors import InputError, require_file
from slam_predict.formats.text_rows import parse_number_row

log = logging.getLogger(__name__)


@dataclass
class Relations:
    """Reference relations: ``t1``, ``t2`` (N,) s and ``deltas`` (N, 3) as (x m, y m, yaw rad)."""

    t1: np.ndarray
    t2: np.ndarray
    deltas: np.ndarray

    def __post_init__(self):
        self.t1 = np.asarray(self.t1, dtype=float).reshape(-1)
        self.t2 = np.asarray(self.t2, dtype=float).reshape(-1)
        self.deltas = np.asarray(self.deltas, dtype=float).reshape(-1, 3)
        if not len(self.t1) == len(self.t2) == len(self.deltas):
            raise ValueError("t1, t2 and deltas must have the same length")

    def __len__(self) -> int:
        return len(self.t1)


def read_relations(path: os.PathLike | str) -> Relations:
    """Read a relations file; InputError (with line number) on a malformed line."""
    path = require_file(path, "relations file")
    rows = []
    try:
        with open(path, encoding="utf-8") as fh:
            for number, line in enumerate(fh, start=1):
                text = line.split("#", 1)[0].strip()
                if text:
                    rows.append(_parse(text, path, number))
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read relations file: {exc}", path) from None
    data = np.array(rows, dtype=float).reshape(-1, 8)
    off_plane = np.abs(data[:, [4, 5, 6]]).max(initial=0.0)
    if off_plane > 1e-9:
        log.warning("%s: non-zero z/roll/pitch (up to %.3g) ignored: planar metric",
                    path, off_plane)
    return Relations(data[:, 0], data[:, 1], data[:, [2, 3, 7]])


def _parse(text: str, path: str, number: int) -> list:
    return parse_number_row(text.split(), "t1 t2 x y z roll pitch yaw", "relation", path, number)


def write_relations(path: os.PathLike | str, relations: Relations,
                    header: Iterable[str] = ()) -> None:
    """Write ``relations`` atomically, full double precision, z = roll = pitch = 0."""
    lines = [f"# {h}" for h in header]
    lines.append("# timestamp1 timestamp2 x y z roll pitch yaw")
    for t1, t2, (x, y, yaw) in zip(relations.t1.tolist(), relations.t2.tolist(),
                                   relations.deltas.tolist(), strict=False):
        lines.append(" ".join(repr(float(v)) for v in (t1, t2, x, y, 0.0, 0.0, 0.0, yaw)))
    write_text(path, "\n".join(lines) + "\n")
