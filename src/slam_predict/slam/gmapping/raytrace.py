"""numba kernels for the published map: Bresenham beams with free-space tracing.

This is openslam_gmapping's ``registerScan`` with ``generateMap=true`` as slam_gmapping's
``updateMap`` uses it: every beam with 0 < r ≤ maxRange is cropped to maxUrange; the cells of the
Bresenham line (GridLineTraversal) from the laser cell to the end cell, end excluded, get a
"free" visit; the end cell gets a hit (and a visit) only when the cropped range is < maxUrange.
Counts go into dense int32 arrays covering the cell window [x0, x0 + w) × [y0, y0 + h) of the
map; cells outside the window are ignored (callers size it with :func:`touched_cells`).
"""
from __future__ import annotations

import math

import numba as nb
import numpy as np

from slam_predict.slam.gmapping.kernels import c_round


@nb.njit(cache=True, inline="always")
def _line_start(x0, y0, x1, y1):
    """GridLineTraversal's walk from (x0, y0) to (x1, y1): it starts at the end with the smaller
    coordinate along the major axis. Returns (x, y, steps, minor_step, d, dx, dy, steep): the
    first cell, the number of steps to the last one, the minor-axis step (±1), the decision
    variable and the absolute deltas; ``steep`` when y is the major axis."""
    dx = abs(x1 - x0)
    dy = abs(y1 - y0)
    steep = dy > dx
    if not steep:
        if x0 > x1:
            return x1, y1, dx, (1 if y0 > y1 else -1), 2 * dy - dx, dx, dy, steep
        return x0, y0, dx, (1 if y1 > y0 else -1), 2 * dy - dx, dx, dy, steep
    if y0 > y1:
        return x1, y1, dy, (1 if x0 > x1 else -1), 2 * dx - dy, dx, dy, steep
    return x0, y0, dy, (1 if x1 > x0 else -1), 2 * dx - dy, dx, dy, steep


@nb.njit(cache=True, inline="always")
def _major_step(major, minor, d, minor_step, d_major, d_minor):
    """One Bresenham step in (major, minor) axis coordinates → (major, minor, d)."""
    if d < 0:
        return major + 1, minor, d + 2 * d_minor
    return major + 1, minor + minor_step, d + 2 * (d_minor - d_major)


@nb.njit(cache=True, inline="always")
def _line_step(x, y, d, minor_step, dx, dy, steep):
    """One Bresenham step along the major axis → (x, y, d)."""
    if steep:
        y, x, d = _major_step(y, x, d, minor_step, dy, dx)
    else:
        x, y, d = _major_step(x, y, d, minor_step, dx, dy)
    return x, y, d


@nb.njit(cache=True)
def line_cells(x0, y0, x1, y1):
    """GridLineTraversal::gridLine: the cells (K, 2) from (x0, y0) to (x1, y1), both included."""
    x, y, steps, minor_step, d, dx, dy, steep = _line_start(x0, y0, x1, y1)
    out = np.empty((steps + 1, 2), dtype=np.int64)
    out[0, 0], out[0, 1] = x, y
    for k in range(1, steps + 1):
        x, y, d = _line_step(x, y, d, minor_step, dx, dy, steep)
        out[k, 0], out[k, 1] = x, y
    if out[0, 0] != x0 or out[0, 1] != y0:
        out = out[::-1].copy()
    return out


@nb.njit(cache=True, inline="always")
def _visit(visits, u, v, sign):
    if 0 <= u < visits.shape[0] and 0 <= v < visits.shape[1]:
        visits[u, v] += sign


@nb.njit(cache=True)
def _count_beam(hits, visits, x0, y0, ax, ay, bx, by, hit, sign):
    """Free visits along the line a → b (b excluded), then the hit at b when ``hit``; each
    count changes by ``sign`` (1 to add the beam, −1 to remove it). The cells are those of
    :func:`line_cells` (walked the same way, without building the list)."""
    x, y, steps, minor_step, d, dx, dy, steep = _line_start(ax, ay, bx, by)
    if x != bx or y != by:
        _visit(visits, x - x0, y - y0, sign)
    for _ in range(steps):
        x, y, d = _line_step(x, y, d, minor_step, dx, dy, steep)
        if x != bx or y != by:
            _visit(visits, x - x0, y - y0, sign)
    if hit:
        u = bx - x0
        v = by - y0
        if 0 <= u < hits.shape[0] and 0 <= v < hits.shape[1]:
            hits[u, v] += sign
            visits[u, v] += sign


@nb.njit(cache=True)
def count_beams(hits, visits, ax, ay, ends_x, ends_y, is_hit):
    """Add beams from cell (ax, ay) to each end cell (ends_x[k], ends_y[k]) into ``hits`` /
    ``visits`` (w, h), indexed [x, y] from cell (0, 0), GMapping's way (:func:`_count_beam`:
    free visits along :func:`line_cells` without the end, a hit and a visit at the end when
    ``is_hit[k]``, nothing there otherwise). Cells outside the arrays are skipped."""
    for k in range(ends_x.shape[0]):
        _count_beam(hits, visits, 0, 0, ax, ay, ends_x[k], ends_y[k], is_hit[k], 1)


@nb.njit(cache=True)
def _beam_cells(x, y, th, r, ca, sa, usable, sx2, sy2, cx, cy, delta):
    """Laser cell, end cell and whether the (cropped) beam ends in a hit."""
    d = min(r, usable)
    c = math.cos(th)
    s = math.sin(th)
    hx = x + d * (c * ca - s * sa)
    hy = y + d * (s * ca + c * sa)
    ax = c_round((x - cx) / delta) + sx2
    ay = c_round((y - cy) / delta) + sy2
    bx = c_round((hx - cx) / delta) + sx2
    by = c_round((hy - cy) / delta) + sy2
    return ax, ay, bx, by, d < usable


@nb.njit(cache=True, inline="always")
def _scan_beam(poses, readings, k, i, ca, sa, max_range, usable, sx2, sy2, cx, cy, delta):
    """Beam i of scan k: (used, laser cell x, y, end cell x, y, hit) as :func:`_beam_cells`
    gives it; ``used`` False (and the rest 0) for a beam GMapping skips (r = 0 or
    r > maxRange)."""
    r = readings[k, i]
    if r > max_range or r == 0.0:
        return False, 0, 0, 0, 0, False
    ax, ay, bx, by, hit = _beam_cells(poses[k, 0], poses[k, 1], poses[k, 2], r, ca[i], sa[i],
                                      usable, sx2, sy2, cx, cy, delta)
    return True, ax, ay, bx, by, hit


@nb.njit(cache=True)
def touched_cells(poses, readings, ca, sa, max_range, usable, sx2, sy2, cx, cy, delta):
    """(ixmin, iymin, ixmax, iymax): cell bounds of every laser and end cell of the scans."""
    lo_x = lo_y = 1 << 40
    hi_x = hi_y = -(1 << 40)
    for k in range(poses.shape[0]):
        for i in range(readings.shape[1]):
            used, ax, ay, bx, by, _ = _scan_beam(poses, readings, k, i, ca, sa, max_range,
                                                 usable, sx2, sy2, cx, cy, delta)
            if not used:
                continue
            lo_x = min(lo_x, ax, bx)
            lo_y = min(lo_y, ay, by)
            hi_x = max(hi_x, ax, bx)
            hi_y = max(hi_y, ay, by)
    return lo_x, lo_y, hi_x, hi_y


@nb.njit(cache=True)
def count_scans(poses, readings, ca, sa, max_range, usable, sx2, sy2, cx, cy, delta,
                x0, y0, w, h):
    """Hit and visit counts (w, h) int32 of the scans (K, B) taken from laser poses (K, 3)."""
    hits = np.zeros((w, h), dtype=np.int32)
    visits = np.zeros((w, h), dtype=np.int32)
    add_scans(hits, visits, poses, readings, ca, sa, max_range, usable, sx2, sy2, cx, cy, delta,
              x0, y0, 1)
    return hits, visits


@nb.njit(cache=True)
def add_scans(hits, visits, poses, readings, ca, sa, max_range, usable, sx2, sy2, cx, cy, delta,
              x0, y0, sign):
    """Add (``sign`` 1) or remove (−1) the scans' counts into ``hits``/``visits`` (w, h), whose
    cell (0, 0) is map cell (x0, y0)."""
    for k in range(poses.shape[0]):
        for i in range(readings.shape[1]):
            used, ax, ay, bx, by, hit = _scan_beam(poses, readings, k, i, ca, sa, max_range,
                                                   usable, sx2, sy2, cx, cy, delta)
            if used:
                _count_beam(hits, visits, x0, y0, ax, ay, bx, by, hit, sign)


@nb.njit(cache=True)
def occupancy_values(hits, visits, occ_thresh):
    """ROS occupancy per cell (w, h) int8: −1 unknown, 100 if n/visits > occ_thresh, else 0."""
    out = np.empty(hits.shape, dtype=np.int8)
    for u in range(hits.shape[0]):
        for v in range(hits.shape[1]):
            if visits[u, v] == 0:
                out[u, v] = -1
            elif hits[u, v] / visits[u, v] > occ_thresh:
                out[u, v] = 100
            else:
                out[u, v] = 0
    return out


def warmup() -> None:
    """Compile (or load from the cache) the kernels of this module on a tiny input."""
    poses = np.zeros((1, 3))
    readings = np.array([[1.0, 0.0, 3.0]])
    ang = np.array([-0.5, 0.0, 0.5])
    ca, sa = np.cos(ang), np.sin(ang)
    geo = (64, 64, 0.0, 0.0, 0.05)
    touched_cells(poses, readings, ca, sa, 2.0, 2.0, *geo)
    hits, visits = count_scans(poses, readings, ca, sa, 2.0, 2.0, *geo, 0, 0, 128, 128)
    occupancy_values(hits, visits, 0.25)
    line_cells(0, 0, 3, -5)
    count_beams(hits.T, visits.T, 2, 3, np.array([5, -1]), np.array([3, 9]),
                np.array([True, False]))
