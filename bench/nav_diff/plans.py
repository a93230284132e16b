"""Captured global-planner requests for the real navfn (``bench/nav_diff/navfn_driver.cpp``).

``plans.bin`` (little-endian): the magic ``SPNAVP01``, then one record per ``make_plan`` call,
tag ``P``: uint32 index; float64 t (s), start x, y, goal x, y (m, costmap frame), tolerance (m);
uint8 allow_unknown; uint32 size_x, size_y; float64 resolution, origin x, origin y (m); uint32 n;
n bytes of zlib-compressed uint8 costs (row-major, my·size_x + mx); the tag ``E`` ends the file.
Our results go to ``ours_plans.npz``: per request found, cost, length (m), end point (m),
reaches_goal, escaped (found only by our start escape), and the poses of all plans (``poses``,
``offsets``). :func:`compare` sets both side by side.
"""
from __future__ import annotations

import struct
from pathlib import Path

import numpy as np

from slam_predict.collect.record import path_length
from slam_predict.errors import InputError, require_file
from slam_predict.formats.nav_cycles import COSTMAP_HEAD, costmap_record

MAGIC = b"SPNAVP01"
_HEAD = struct.Struct("<IddddddB")


class PlanWriter:
    """Writes ``plans.bin`` and, on :meth:`close`, ``ours_plans.npz``."""

    def __init__(self, folder: Path):
        self.folder = folder
        self._file = open(folder / "plans.bin", "wb")
        self._file.write(MAGIC)
        self.rows: list[list[float]] = []
        self.poses: list[np.ndarray] = []

    def add(self, t: float, costmap, start, goal, tol: float, allow_unknown: bool, plan,
            escaped: bool) -> None:
        """One request (costmap frame) and our plan (None when none was found; ``escaped``:
        found only by the start escape)."""
        self._file.write(b"P" + _HEAD.pack(len(self.rows), t, float(start[0]), float(start[1]),
                                           float(goal[0]), float(goal[1]), tol,
                                           int(allow_unknown)))
        self._file.write(costmap_record(costmap))
        if plan is None:
            self.rows.append([t, 0, np.nan, np.nan, np.nan, np.nan, 0, 0])
            self.poses.append(np.empty((0, 2)))
        else:
            end = plan.poses[-1, :2]
            self.rows.append([t, 1, plan.cost, plan.length, end[0], end[1],
                              float(plan.reaches_goal), float(escaped)])
            self.poses.append(np.asarray(plan.poses[:, :2], dtype=float))

    def close(self) -> int:
        self._file.write(b"E")
        self._file.close()
        rows = np.array(self.rows, dtype=float).reshape(-1, 8)
        names = ("t", "found", "cost", "length", "end_x", "end_y", "reaches_goal", "escaped")
        offsets = np.cumsum([0] + [len(p) for p in self.poses])
        poses = np.concatenate(self.poses) if self.poses else np.empty((0, 2))
        np.savez_compressed(self.folder / "ours_plans.npz", poses=poses, offsets=offsets,
                            **{n: rows[:, k] for k, n in enumerate(names)})
        return len(self.rows)


def read_navfn_output(path: Path) -> list[np.ndarray]:
    """The navfn driver's plans: one (n, 2) array per request (empty: no plan). Its text is
    ``navfn_diff_driver 1`` then per request ``index n x_0 y_0 ... x_n-1 y_n-1``."""
    lines = Path(require_file(path, "navfn driver output")).read_text().splitlines()
    if not lines or lines[0].strip() != "navfn_diff_driver 1":
        raise InputError(f"{path}: not a navfn driver output")
    out = []
    for line in lines[1:]:
        values = line.split()
        n = int(values[1])
        out.append(np.array(values[2:2 + 2 * n], dtype=float).reshape(n, 2))
    return out


def request_widths(path: Path) -> np.ndarray:
    """size_x (cells) of each request's costmap in ``plans.bin``."""
    data = Path(require_file(path, "captured plans")).read_bytes()
    if data[:8] != MAGIC:
        raise InputError(f"{path}: not a captured-plans file ({MAGIC.decode()})")
    at, widths = 8, []
    while data[at:at + 1] == b"P":
        at += 1 + _HEAD.size
        size_x, _, _, _, _, n = COSTMAP_HEAD.unpack_from(data, at)
        widths.append(size_x)
        at += COSTMAP_HEAD.size + n
    if data[at:at + 1] != b"E":
        raise InputError(f"{path}: bad record at byte {at}")
    return np.array(widths, dtype=np.int64)


def _hausdorff(a: np.ndarray, b: np.ndarray) -> float:
    """Hausdorff distance (m) of two point sets (n, 2), (m, 2)."""
    d = np.hypot(a[:, None, 0] - b[None, :, 0], a[:, None, 1] - b[None, :, 1])
    return float(max(d.min(axis=1).max(), d.min(axis=0).max()))


def compare(ours: dict, real: list[np.ndarray], widths: np.ndarray) -> list[str]:
    """Table cells: requests; found ours / real; agreement (%); ours only, of which by the start
    escape; real only; real plans whose descent stopped at calcPath's cycle limit (4·size_x
    points, not reaching the robot: NavfnROS::getPlanFromPotential ignores calcPath's result);
    same end point within 1 cm (%); length ours ÷ real, median over plans of ≥ 1 m; Hausdorff
    distance median / max (m), both over the other plans found by both."""
    found_real = np.array([len(p) > 0 for p in real])
    failed = np.array([len(p) >= 4 * w + 1 for p, w in zip(real, widths, strict=True)])
    found_ours = ours["found"] > 0
    only = found_ours & ~found_real
    both = np.nonzero(found_ours & found_real & ~failed)[0]
    ends, ratios, gaps = [], [], []
    for k in both:
        mine = ours["poses"][ours["offsets"][k]:ours["offsets"][k + 1]]
        ends.append(np.hypot(*(mine[-1] - real[k][-1])) <= 0.01)
        if path_length(real[k]) >= 1.0:
            ratios.append(path_length(mine) / path_length(real[k]))
        gaps.append(_hausdorff(mine, real[k]))
    n = len(real)
    return [str(n), f"{found_ours.sum()} / {found_real.sum()}",
            f"{100 * np.mean(found_ours == found_real):.1f}",
            f"{only.sum()} ({int((only & (ours['escaped'] > 0)).sum())})",
            f"{found_real.sum() - (found_ours & found_real).sum()}", str(int(failed.sum())),
            f"{100 * np.mean(ends):.1f}" if ends else "–",
            f"{np.median(ratios):.3f}" if ratios else "–",
            f"{np.median(gaps):.3f} / {max(gaps):.3f}" if gaps else "–"]
