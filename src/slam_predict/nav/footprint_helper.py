"""base_local_planner's FootprintHelper: the cells under the robot's footprint polygon, as the
real planner rasterises them (Bresenham lines along the outline, then every column filled between
its lowest and highest outline cell). MapGrid exempts these cells from the path grid's obstacle
test. nav/costmap.py ``footprint_cells`` is the project's own rule (cell centres inside the
polygon grown by half a cell); ``upstream_rules`` selects this one.
"""
from __future__ import annotations

import math

import numba as nb
import numpy as np

from slam_predict.nav.costmap import Costmap


@nb.njit(cache=True)
def _line_length(x0, y0, x1, y1):
    return max(abs(x1 - x0), abs(y1 - y0)) + 1


@nb.njit(cache=True)
def _draw_line(out, n, x0, y0, x1, y1):
    """FootprintHelper::getLineCells from (x0, y0) to (x1, y1), both ends included, written
    into ``out`` from row ``n`` on (the major axis steps every cell) → the next free row."""
    dx, dy = abs(x1 - x0), abs(y1 - y0)
    sx = 1 if x1 >= x0 else -1
    sy = 1 if y1 >= y0 else -1
    major_x = dx >= dy
    den, numadd = (dx, dy) if major_x else (dy, dx)
    num, x, y = den // 2, x0, y0
    for _ in range(den + 1):
        out[n, 0] = x
        out[n, 1] = y
        n += 1
        num += numadd
        if num >= den:
            num -= den
            if major_x:
                y += sy
            else:
                x += sx
        if major_x:
            x += sx
        else:
            y += sy
    return n


@nb.njit(cache=True)
def _fill_spans(cells, emit, out, n):
    """getFillCells' loop over the column-sorted outline ``cells``: for each column, the cells
    from its lowest outline cell up to (not including) its highest. Counts them when ``emit`` is
    False, writes them into ``out`` from row ``n`` when True → the row after the last."""
    i = 0
    m = cells.shape[0]
    for x in range(cells[0, 0], cells[m - 1, 0] + 1):
        if i >= m - 1:
            break
        lo = min(cells[i, 1], cells[i + 1, 1])
        hi = max(cells[i, 1], cells[i + 1, 1])
        i += 2
        while i < m and cells[i, 0] == x:
            lo = min(lo, cells[i, 1])
            hi = max(hi, cells[i, 1])
            i += 1
        for y in range(lo, hi):
            if emit:
                out[n, 0] = x
                out[n, 1] = y
            n += 1
    return n


@nb.njit(cache=True)
def outline_and_fill(corners, edges, fill):
    """(m, 2) cells of the first ``edges`` edges of the polygon ``corners`` (n, 2) in map cells
    (edge k runs from corner k to corner k+1, the last back to corner 0), then, when ``fill``,
    getFillCells' cells. Upstream sorts the outline with an in-place exchange sort that swaps
    only on a strictly greater column, so a stable sort by column gives its order."""
    k_corners = corners.shape[0]
    total = 0
    for k in range(edges):
        a, b = corners[k], corners[(k + 1) % k_corners]
        total += _line_length(a[0], a[1], b[0], b[1])
    outline = np.empty((total, 2), np.int64)
    n = 0
    for k in range(edges):
        a, b = corners[k], corners[(k + 1) % k_corners]
        n = _draw_line(outline, n, a[0], a[1], b[0], b[1])
    if not fill or total == 0:
        return outline
    outline = outline[np.argsort(outline[:, 0], kind="mergesort")]
    extra = _fill_spans(outline, False, outline, 0)
    out = np.empty((total + extra, 2), np.int64)
    out[:total] = outline
    _fill_spans(outline, True, out, total)
    return out


def footprint_cells_upstream(costmap: Costmap, pose, footprint: np.ndarray) -> np.ndarray:
    """(n, 2) cells (mx, my) of the footprint (vertices in m, robot frame) at ``pose`` (x m, y m,
    θ rad), outline and fill, duplicates kept as upstream keeps them. An edge with a vertex off
    the map ends the outline there, unfilled (FootprintHelper::getFootprintCells returns the
    cells it has by then)."""
    x, y, th = (float(v) for v in pose[:3])
    c, s = math.cos(th), math.sin(th)
    corners = [costmap.world_to_map(x + (fx * c - fy * s), y + (fx * s + fy * c))
               for fx, fy in footprint]
    edges = len(corners)
    for k, a in enumerate(corners):
        if a is None or corners[(k + 1) % len(corners)] is None:
            edges = k
            break
    table = np.array([a if a is not None else (0, 0) for a in corners], np.int64).reshape(-1, 2)
    return outline_and_fill(table, edges, edges == len(corners))


def warmup() -> None:
    """Compile the kernel on a unit square."""
    outline_and_fill(np.array([[0, 0], [0, 2], [2, 2], [2, 0]], np.int64), 4, True)
