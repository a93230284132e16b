"""numba kernels of the frontier search: the frontier cells of an occupancy grid, their
clusters and the free space joined to the robot (:func:`free_component`).

Grids are occupancy values (int8: -1 unknown, 0 free, > 0 occupied), indexed ``[row, col]``.
:func:`roomy_unknown` and :func:`frontier_cells` compute what
:func:`slam_predict.explore.frontiers.frontier_mask` defines (its docstring), cell for cell, with
prefix sums for the square erosion and a flood fill for the propagation instead of scipy's
filter and two labelings. ``warmup()`` compiles them (listed in :mod:`slam_predict.warmup`).
"""
from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True)
def _square_cores(unknown: np.ndarray, width: int) -> np.ndarray:
    """Cells whose ``width`` × ``width`` window (rows and columns from ``i - width // 2``,
    scipy's window for a filter of that size) holds no known cell; cells beyond the array
    count as unknown. Row prefix sums of known cells, then column prefix sums of the rows'
    verdicts (uint8 [h, w]: 1 = a core cell)."""
    h, w = unknown.shape
    lo = width // 2
    row_known = np.zeros((h, w), np.uint8)          # a known cell in the row window
    prefix = np.zeros(w + 1, np.int32)
    for r in range(h):
        for c in range(w):
            prefix[c + 1] = prefix[c] + (0 if unknown[r, c] else 1)
        for c in range(w):
            a = max(c - lo, 0)
            b = min(c - lo + width, w)
            if a < b and prefix[b] > prefix[a]:
                row_known[r, c] = 1
    column = np.zeros((h + 1, w), np.int32)          # column prefix sums of row_known
    for r in range(h):
        for c in range(w):
            column[r + 1, c] = column[r, c] + row_known[r, c]
    core = np.zeros((h, w), np.uint8)
    for r in range(h):
        a = max(r - lo, 0)
        b = min(r - lo + width, h)
        if a >= b:
            for c in range(w):
                core[r, c] = 1
            continue
        for c in range(w):
            if column[b, c] == column[a, c]:
                core[r, c] = 1
    return core


@numba.njit(cache=True)
def roomy_unknown(unknown: np.ndarray, width: int) -> np.ndarray:
    """The cells of ``unknown`` (bool [h, w]) 4-connected, through unknown cells, to a
    ``width`` × ``width`` square of unknown cells (cells beyond the array count as unknown);
    ``width`` <= 1: a copy of ``unknown``."""
    h, w = unknown.shape
    if width <= 1:
        return unknown.copy()
    core = _square_cores(unknown, width)
    roomy = np.zeros((h, w), np.bool_)
    stack_r = np.empty(h * w, np.int32)
    stack_c = np.empty(h * w, np.int32)
    for r in range(h):
        for c in range(w):
            if core[r, c] == 0 or roomy[r, c]:
                continue
            roomy[r, c] = True                       # a square's cell: flood from it
            stack_r[0], stack_c[0] = r, c
            top = 1
            while top > 0:
                top -= 1
                rr, cc = stack_r[top], stack_c[top]
                if rr > 0 and unknown[rr - 1, cc] and not roomy[rr - 1, cc]:
                    roomy[rr - 1, cc] = True
                    stack_r[top], stack_c[top] = rr - 1, cc
                    top += 1
                if rr + 1 < h and unknown[rr + 1, cc] and not roomy[rr + 1, cc]:
                    roomy[rr + 1, cc] = True
                    stack_r[top], stack_c[top] = rr + 1, cc
                    top += 1
                if cc > 0 and unknown[rr, cc - 1] and not roomy[rr, cc - 1]:
                    roomy[rr, cc - 1] = True
                    stack_r[top], stack_c[top] = rr, cc - 1
                    top += 1
                if cc + 1 < w and unknown[rr, cc + 1] and not roomy[rr, cc + 1]:
                    roomy[rr, cc + 1] = True
                    stack_r[top], stack_c[top] = rr, cc + 1
                    top += 1
    return roomy


@numba.njit(cache=True)
def frontier_cells(data: np.ndarray, width: int) -> np.ndarray:
    """Free cells (0) of ``data`` (int8 [h, w]) with a 4-neighbour in :func:`roomy_unknown` of
    its unknown cells (-1); neighbours beyond the array do not count."""
    h, w = data.shape
    roomy = roomy_unknown(data == -1, width)
    out = np.zeros((h, w), np.bool_)
    for r in range(h):
        for c in range(w):
            if data[r, c] == 0 and ((r > 0 and roomy[r - 1, c]) or (r + 1 < h and roomy[r + 1, c])
                                    or (c > 0 and roomy[r, c - 1])
                                    or (c + 1 < w and roomy[r, c + 1])):
                out[r, c] = True
    return out


@numba.njit(cache=True)
def clusters_in_raster_order(mask: np.ndarray):
    """The 8-connected components of ``mask`` (bool [h, w]) numbered by their first cell in
    raster order, as scipy's ``ndimage.label`` numbers them: (rows, cols) of every cell
    (int64), grouped by component and in raster order within one, and ``starts`` (int64
    [count + 1]): component k's cells are ``starts[k]:starts[k + 1]``."""
    h, w = mask.shape
    labels = np.zeros((h, w), np.int32)
    stack_r = np.empty(h * w, np.int32)
    stack_c = np.empty(h * w, np.int32)
    count = 0
    for r in range(h):
        for c in range(w):
            if not mask[r, c] or labels[r, c] != 0:
                continue
            count += 1
            labels[r, c] = count
            stack_r[0], stack_c[0] = r, c
            top = 1
            while top > 0:
                top -= 1
                rr, cc = stack_r[top], stack_c[top]
                for nr in range(max(rr - 1, 0), min(rr + 2, h)):
                    for nc in range(max(cc - 1, 0), min(cc + 2, w)):
                        if mask[nr, nc] and labels[nr, nc] == 0:
                            labels[nr, nc] = count
                            stack_r[top], stack_c[top] = nr, nc
                            top += 1
    starts = np.zeros(count + 1, np.int64)
    for r in range(h):
        for c in range(w):
            if labels[r, c] != 0:
                starts[labels[r, c]] += 1
    for k in range(count):
        starts[k + 1] += starts[k]
    fill = starts[:-1].copy()
    rows = np.empty(starts[count], np.int64)
    cols = np.empty(starts[count], np.int64)
    for r in range(h):
        for c in range(w):
            k = labels[r, c] - 1
            if k >= 0:
                rows[fill[k]] = r
                cols[fill[k]] = c
                fill[k] += 1
    return rows, cols, starts


@numba.njit(cache=True)
def free_component(data: np.ndarray, row: int, col: int) -> np.ndarray:
    """The free (0) cells 4-connected, through free cells, to the free cell nearest
    (``row``, ``col``): explore_lite's frontier search, which starts at the free cell a
    breadth-first search over all cells finds first from the robot's cell (``nearestCell``) and
    spreads over free 4-neighbours. All False when the grid has no free cell."""
    h, w = data.shape
    out = np.zeros((h, w), np.bool_)
    seen = np.zeros((h, w), np.bool_)
    queue = np.empty(h * w, np.int32)
    dr = (-1, 1, 0, 0)
    dc = (0, 0, -1, 1)
    queue[0] = row * w + col
    seen[row, col] = True
    head, tail, start = 0, 1, -1
    while head < tail:
        idx = queue[head]
        head += 1
        r, c = idx // w, idx % w
        if data[r, c] == 0:
            start = idx
            break
        for k in range(4):
            rr, cc = r + dr[k], c + dc[k]
            if 0 <= rr < h and 0 <= cc < w and not seen[rr, cc]:
                seen[rr, cc] = True
                queue[tail] = rr * w + cc
                tail += 1
    if start < 0:
        return out
    queue[0] = start
    out[start // w, start % w] = True
    head, tail = 0, 1
    while head < tail:
        idx = queue[head]
        head += 1
        r, c = idx // w, idx % w
        for k in range(4):
            rr, cc = r + dr[k], c + dc[k]
            if 0 <= rr < h and 0 <= cc < w and not out[rr, cc] and data[rr, cc] == 0:
                out[rr, cc] = True
                queue[tail] = rr * w + cc
                tail += 1
    return out


def warmup() -> None:
    """Compile the kernels on a tiny grid."""
    grid = np.full((8, 8), -1, np.int8)
    grid[2:6, 2:6] = 0
    clusters_in_raster_order(frontier_cells(grid, 3))
    frontier_cells(grid, 0)
    free_component(grid, 0, 0)
