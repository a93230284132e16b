"""Timestamp association of two trajectories, and the thesis' log adjustments.

Association rule (documented, one-to-one): each timestamp of A is matched to the nearest
timestamp of B (ties → the earlier one); a match further apart than ``tol`` seconds is dropped;
when several A stamps choose the same B stamp, only the closest keeps it (ties → the earliest A).
Both inputs must be sorted non-decreasingly; the output index arrays are strictly increasing.

Adjustments (thesis §6.2, ``adjust_metric.py`` / ``adjust_output.py``): consecutive repeated poses
(pauses) are reduced to one instance; a truncated last log line is dropped (the CARMEN and TUM
readers already drop it; :func:`drop_truncated_last_line` repairs a file in place).
"""
from __future__ import annotations

import gzip
import logging
import os

import numpy as np

from slam_predict.atomic import write_bytes
from slam_predict.errors import InputError, require_file

log = logging.getLogger(__name__)


def associate(t_a, t_b, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Indices (ia, ib) of one-to-one nearest-timestamp matches within ``tol`` s."""
    t_a = np.asarray(t_a, dtype=float).reshape(-1)
    t_b = np.asarray(t_b, dtype=float).reshape(-1)
    if len(t_a) == 0 or len(t_b) == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    if np.any(np.diff(t_a) < 0) or np.any(np.diff(t_b) < 0):
        raise ValueError("timestamps must be sorted")
    right = np.clip(np.searchsorted(t_b, t_a, side="left"), 0, len(t_b) - 1)
    left = np.clip(right - 1, 0, len(t_b) - 1)
    left = np.searchsorted(t_b, t_b[left], side="left")   # first of equal stamps
    d_left = np.abs(t_a - t_b[left])
    d_right = np.abs(t_b[right] - t_a)
    nearest = np.where(d_left <= d_right, left, right)
    dist = np.minimum(d_left, d_right)
    ia = np.flatnonzero(dist <= tol)
    ib = nearest[ia]
    if len(ia) == 0:
        return ia, ib
    # Resolve shared B stamps: keep the closest A (stable sort → earliest on ties).
    order = np.lexsort((ia, dist[ia], ib))
    first = np.ones(len(order), bool)
    first[1:] = ib[order][1:] != ib[order][:-1]
    keep = np.sort(order[first])
    return ia[keep], ib[keep]


def nearest_within(t_query, t, tol: float) -> np.ndarray:
    """Index of the nearest stamp in sorted ``t`` for each query, or −1 when further than ``tol``.

    Not one-to-one: this is how metricEvaluator finds a pose for a relation timestamp.
    """
    t = np.asarray(t, dtype=float).reshape(-1)
    q = np.asarray(t_query, dtype=float).reshape(-1)
    if len(t) == 0:
        return np.full(len(q), -1, np.int64)
    right = np.clip(np.searchsorted(t, q), 0, len(t) - 1)
    left = np.clip(right - 1, 0, len(t) - 1)
    left = np.searchsorted(t, t[left], side="left")   # first of equal stamps
    use_left = np.abs(q - t[left]) <= np.abs(t[right] - q)
    idx = np.where(use_left, left, right)
    idx[np.abs(t[idx] - q) > tol] = -1
    return idx


def dedupe_mask(poses, atol: float = 0.0) -> np.ndarray:
    """Boolean mask keeping the first of each run of consecutive repeated poses.

    A pose repeats the previous kept one when every component differs by ≤ ``atol`` (m, rad).
    """
    poses = np.asarray(poses, dtype=float).reshape(-1, 3)
    keep = np.ones(len(poses), bool)
    if len(poses) < 2:
        return keep
    if atol == 0.0:
        keep[1:] = np.any(poses[1:] != poses[:-1], axis=1)
        return keep
    last = poses[0]
    for i in range(1, len(poses)):
        if np.all(np.abs(poses[i] - last) <= atol):
            keep[i] = False
        else:
            last = poses[i]
    return keep


def dedupe_consecutive(t, poses, atol: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(t, poses) without consecutive repeated poses (the thesis' pause removal)."""
    mask = dedupe_mask(poses, atol)
    removed = int((~mask).sum())
    if removed:
        log.debug("removed %d repeated poses of %d", removed, len(mask))
    return np.asarray(t, float)[mask], np.asarray(poses, float).reshape(-1, 3)[mask]


def drop_truncated_last_line(path: os.PathLike | str, out: os.PathLike | str | None = None,
                             kind: str = "auto") -> bool:
    """Remove the last line of a CARMEN or TUM file if it is truncated; True if one was removed.

    The file (or ``out``) is rewritten atomically. ``kind``: 'carmen', 'tum' or 'auto' (TUM when
    the first data line has 8 numeric fields).
    """
    path = require_file(path, "trajectory log")
    with open(path, "rb") as fh:
        data = fh.read()
    compressed = data[:2] == b"\x1f\x8b"
    if compressed:
        try:
            data = gzip.decompress(data)
        except (OSError, EOFError) as exc:
            raise InputError(f"cannot decompress: {exc}", path) from None
    lines = data.splitlines(keepends=True)
    last = next((i for i in range(len(lines) - 1, -1, -1) if lines[i].strip()), None)
    removed = last is not None and _is_truncated(lines, last, kind, path)
    if removed:
        log.warning("%s: dropping truncated last line %d", path, last + 1)
        data = b"".join(lines[:last])
    if removed or out is not None:
        write_bytes(out if out is not None else path, gzip.compress(data) if compressed else data)
    return removed


def _is_truncated(lines, index: int, kind: str, path: str) -> bool:
    text = lines[index].decode("utf-8", errors="replace")
    if kind == "auto":
        kind = _guess_kind(lines)
    tokens = text.split()
    if kind == "tum":
        return not text.startswith("#") and (len(tokens) < 8 or not _numeric(tokens))
    if kind != "carmen":
        raise InputError(f"unknown log kind {kind!r} (carmen or tum)", path)
    from slam_predict.formats.carmen_lines import line_status

    status = line_status(tokens)
    return status == "truncated" or (status == "malformed" and not text.endswith("\n"))


def _guess_kind(lines) -> str:
    for raw in lines:
        tokens = raw.decode("utf-8", errors="replace").split()
        if tokens and not tokens[0].startswith("#"):
            return "tum" if len(tokens) == 8 and _numeric(tokens) else "carmen"
    return "carmen"


def _numeric(tokens) -> bool:
    try:
        [float(t) for t in tokens]
        return True
    except ValueError:
        return False
