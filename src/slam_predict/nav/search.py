"""The global planner's search runs: per-cell costs as codes into a cost table, work arrays
kept from search to search, and a search that pauses to learn which goal cells no path
reaches (:func:`search_codes`). The search itself is :func:`slam_predict.nav.kernels.grid_search`.
"""
from __future__ import annotations

import numpy as np
from scipy import ndimage

from slam_predict.nav import kernels


class SearchWork:
    """The per-cell work arrays of :func:`kernels.grid_search`, kept from search to search
    with a search number, so a plan over millions of cells clears none of them; also the cost
    codes of the searched box and the heap storage."""

    def __init__(self):
        self.g = np.empty(0)
        self.parent = np.empty(0, np.int32)
        self.mark = np.zeros(0, np.int32)
        self.stamp = 0
        self._codes = np.empty(0, np.uint16)
        self.keys = np.empty(0)
        self.vals = np.empty(0, np.int32)

    def next_search(self, cells: int) -> int:
        """The number of the next search over ``cells`` cells (arrays grown to fit)."""
        if self.g.size < cells:
            self.g = np.empty(cells)
            self.parent = np.empty(cells, np.int32)
            self.mark = np.zeros(cells, np.int32)
        self.stamp += 1
        return self.stamp

    def codes(self, shape: tuple[int, int]) -> np.ndarray:
        """A C-contiguous uint16 array of ``shape`` (contents undefined)."""
        cells = shape[0] * shape[1]
        if self._codes.size < cells:
            self._codes = np.empty(cells, np.uint16)
        return self._codes[:cells].reshape(shape)

    def heap(self, cap: int) -> tuple[np.ndarray, np.ndarray]:
        """Heap storage (keys, values) of at least ``cap`` entries (contents undefined)."""
        if self.keys.size < cap:
            self.keys = np.empty(cap)
            self.vals = np.empty(cap, np.int32)
        return self.keys, self.vals


def search_costs(cell_cost: np.ndarray, start, goal, tol_cells: int,
                 work: SearchWork | None = None, pause: int | None = None):
    """:func:`kernels.grid_search` over per-cell costs (float [ny, nx], inf = blocked) from
    ``start`` to the goal window (cells): each distinct cost becomes a code; returns (path
    cells (n, 2), cost). ``work``: the planner's :class:`SearchWork` (a new one when None)."""
    table, codes = np.unique(cell_cost, return_inverse=True)
    if len(table) > np.iinfo(np.uint16).max + 1:
        raise ValueError("more distinct cell costs than uint16 codes")
    codes = np.ascontiguousarray(codes.reshape(cell_cost.shape).astype(np.uint16))
    return search_codes(codes, table.astype(np.float64), start, goal, tol_cells, work, pause)


def search_codes(codes: np.ndarray, table: np.ndarray, start, goal, tol_cells: int,
                 work: SearchWork | None = None, pause: int | None = None):
    """:func:`kernels.grid_search` over cells costing ``table[codes]`` from ``start`` to the
    goal window, growing the heap storage until it fits; returns (path cells (n, 2), cost).
    The heuristic weight is the smallest cell cost, at most 1 (inf, blocked, never lowers it).

    A search that has settled ``pause`` cells (default: an eighth of them, at least
    PAUSE_CELLS) without ending pauses; it resumes told which window cells no path reaches
    (:func:`_reachable_window_left`), so a goal whose window is partly walled off ends once
    the reachable part is settled instead of after the whole map, with the same result."""
    work = work or SearchWork()
    weight = 1.0 if table.min() >= 1.0 else float(np.min(table[codes], initial=1.0))
    (sx, sy), (gx, gy) = start, goal
    window = (gx - tol_cells, gy - tol_cells, gx + tol_cells, gy + tol_cells)
    cap = max(1024, 2 * codes.size)
    budget = max(PAUSE_CELLS, codes.size // 8) if pause is None else int(pause)
    while True:
        stamp = work.next_search(codes.size)
        keys, vals = work.heap(cap)
        args = (codes, table, sx, sy, gx, gy, *window, min(weight, 50.0), keys, vals, work.g,
                work.parent, work.mark, stamp)
        path, cost, status, size = kernels.grid_search(*args, 0, -1, budget)
        if status == 1:
            left = _reachable_window_left(codes, table, start, window, work.mark, stamp)
            path, cost, status, _ = kernels.grid_search(*args, size, left, -1)
        if status == 0:
            return path, cost
        cap *= 2


PAUSE_CELLS = 100_000   # a search pauses after settling at least this many cells


def _reachable_window_left(codes: np.ndarray, table: np.ndarray, start, window,
                           mark: np.ndarray, stamp: int) -> int:
    """The window cells a search counts (traversable, or the start) that a path from
    ``start`` reaches (8-connected over traversable cells, as the search moves) and that the
    paused search has not settled yet."""
    ny, nx = codes.shape
    sx, sy = start
    passable = np.isfinite(table[codes])
    labels, _ = ndimage.label(passable, structure=np.ones((3, 3), bool))
    near = labels[max(sy - 1, 0):sy + 2, max(sx - 1, 0):sx + 2]
    ids = np.unique(near[near > 0])
    x0, y0 = max(window[0], 0), max(window[1], 0)
    x1, y1 = min(window[2], nx - 1) + 1, min(window[3], ny - 1) + 1
    if x0 >= x1 or y0 >= y1:
        return 0
    counted = np.isin(labels[y0:y1, x0:x1], ids)
    if x0 <= sx < x1 and y0 <= sy < y1:
        counted[sy - y0, sx - x0] = True
    unsettled = mark[:ny * nx].reshape(ny, nx)[y0:y1, x0:x1] != 2 * stamp + 1
    return int(np.count_nonzero(counted & unsettled))
