"""base_local_planner's FootprintHelper: the cells under the robot's footprint polygon, as the
real planner rasterises them (Bresenham lines along the outline, then every column filled between
its lowest and highest outline cell). MapGrid exempts these cells from the path grid's obstacle
test. nav/costmap.py ``footprint_cells`` is the project's own rule (cell centres inside the
polygon grown by half a cell); ``upstream_rules`` selects this one.
"""
from __future__ import annotations

import math
from itertools import repeat

import numpy as np

from slam_predict.nav.costmap import Costmap


def line_cells(x0: int, y0: int, x1: int, y1: int) -> list[tuple[int, int]]:
    """The Bresenham cells from (x0, y0) to (x1, y1), both ends included
    (FootprintHelper::getLineCells: the major axis steps every cell)."""
    dx, dy = abs(x1 - x0), abs(y1 - y0)
    sx, sy = (1 if x1 >= x0 else -1), (1 if y1 >= y0 else -1)
    major_x = dx >= dy
    den, numadd = (dx, dy) if major_x else (dy, dx)
    num, x, y = den // 2, x0, y0
    out = []
    for _ in range(den + 1):
        out.append((x, y))
        num += numadd
        if num >= den:
            num -= den
            x, y = (x, y + sy) if major_x else (x + sx, y)
        x, y = (x + sx, y) if major_x else (x, y + sy)
    return out


def fill_cells(cells: list[tuple[int, int]]) -> None:
    """FootprintHelper::getFillCells: sort the outline cells by column, then append every cell
    from each column's lowest outline cell up to (not including) its highest.

    Upstream sorts with an in-place exchange sort that swaps only on a strictly greater x, so
    cells of one column keep their order: a stable sort by x gives the same list (and is what
    runs here: the exchange sort is quadratic and took 40 % of an episode's CPU)."""
    cells.sort(key=_column)
    i = 0
    for x in range(cells[0][0], cells[-1][0] + 1):
        if i >= len(cells) - 1:
            break
        lo, hi = ((cells[i], cells[i + 1]) if cells[i][1] < cells[i + 1][1]
                  else (cells[i + 1], cells[i]))
        i += 2
        while i < len(cells) and cells[i][0] == x:
            if cells[i][1] < lo[1]:
                lo = cells[i]
            elif cells[i][1] > hi[1]:
                hi = cells[i]
            i += 1
        cells.extend(zip(repeat(x), range(lo[1], hi[1])))


def _column(cell: tuple[int, int]) -> int:
    return cell[0]


def footprint_cells_upstream(costmap: Costmap, pose, footprint: np.ndarray) -> np.ndarray:
    """(n, 2) cells (mx, my) of the footprint (vertices in m, robot frame) at ``pose`` (x m, y m,
    θ rad), outline and fill, duplicates kept as upstream keeps them. An edge with a vertex off
    the map ends the outline there, unfilled (FootprintHelper::getFootprintCells returns the
    cells it has by then)."""
    x, y, th = (float(v) for v in pose[:3])
    c, s = math.cos(th), math.sin(th)
    corners = [costmap.world_to_map(x + (fx * c - fy * s), y + (fx * s + fy * c))
               for fx, fy in footprint]
    cells: list[tuple[int, int]] = []
    for k, a in enumerate(corners):   # edges 0-1, 1-2, ..., (n-1)-0
        b = corners[(k + 1) % len(corners)]
        if a is None or b is None:
            return np.array(cells, dtype=np.int64).reshape(-1, 2)
        cells += line_cells(a[0], a[1], b[0], b[1])
    fill_cells(cells)
    return np.array(cells, dtype=np.int64).reshape(-1, 2)
