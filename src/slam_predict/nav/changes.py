"""Where a costs grid was written since a reader last looked, so readers compare only there.

:class:`WriteLog` lists, in order, the boxes written into one costs array (the layered costmap,
the only writer of its costmap's costs, records each update's box). A reader remembers the
log's :attr:`WriteLog.count` when it looks at the grid; later, :meth:`WriteLog.since` gives a
box holding every cell written in between (None: none was), and every cell outside it still
holds what the reader saw. Readers:

* :class:`KnownBox`: the bounding box of the cells other than a value (the global planner's
  known cells), updated from the written box instead of a pass over the whole grid;
* the global planner's plan cache (:class:`slam_predict.nav.planner.LastPlan`) compares the
  costs with its copy only inside the written box.

A grid without a log (or whose log is about another array) is read whole, as before.
:func:`known_union` bounds where two SLAM maps that tell their ``known`` boxes can differ.
"""
from __future__ import annotations

import numba
import numpy as np

Bounds = tuple[int, int, int, int]  # (x0, y0, x1, y1) cells, end-exclusive


class WriteLog:
    """The boxes written into the grid ``costs`` (uint8 [ny, nx]), write n (1-based) being
    the n-th :meth:`record`. Only the last ``keep`` to ``2 * keep`` boxes are kept; a reader
    further behind is told the whole grid."""

    def __init__(self, costs: np.ndarray, keep: int = 1024):
        self.costs = costs
        self.count = 0
        self.keep = int(keep)
        self._boxes: list[Bounds] = []
        self._first = 0          # writes before self._boxes[0]

    def record(self, box: Bounds) -> None:
        """A write into the cells [x0, x1) x [y0, y1) (kept clipped to the grid)."""
        ny, nx = self.costs.shape
        x0, y0, x1, y1 = (int(v) for v in box)
        self._boxes.append((min(max(x0, 0), nx), min(max(y0, 0), ny),
                            min(max(x1, 0), nx), min(max(y1, 0), ny)))
        self.count += 1
        if len(self._boxes) > 2 * self.keep:
            del self._boxes[:self.keep]
            self._first += self.keep

    def since(self, count: int) -> Bounds | None:
        """A box holding every cell written after write ``count`` (None: nothing written; the
        whole grid when those writes are no longer kept)."""
        if count >= self.count:
            return None
        if count < self._first:
            return (0, 0, int(self.costs.shape[1]), int(self.costs.shape[0]))
        boxes = self._boxes[count - self._first:]
        return (min(b[0] for b in boxes), min(b[1] for b in boxes),
                max(b[2] for b in boxes), max(b[3] for b in boxes))


def log_of(costmap) -> WriteLog | None:
    """The write log of a costmap-like object (``costs`` and maybe ``log``), when it is about
    that object's current ``costs`` array; else None."""
    log = getattr(costmap, "log", None)
    if log is None or log.costs is not costmap.costs:
        return None
    return log


def known_union(a, b, shape) -> tuple[int, int, int, int] | None:
    """The box holding two grids' ``known`` boxes, clipped to ``shape`` (rows, columns):
    outside it both grids are all −1 (``OccupancyGrid.known``); None when either has no box."""
    if a is None or b is None:
        return None
    ny, nx = shape
    return (max(0, min(a[0], b[0])), max(0, min(a[1], b[1])),
            min(nx, max(a[2], b[2])), min(ny, max(a[3], b[3])))


class KnownBox:
    """The bounding box of the cells of a costs grid other than ``value`` (uint8), kept from
    one call to the next: a later call on a logged grid scans only the written box and the
    edges of the old box; otherwise the whole grid (:func:`other_box_within` of it all)."""

    def __init__(self, value: int):
        self.value = np.uint8(value)
        self._log: WriteLog | None = None
        self._count = 0
        self._box: Bounds = (-1, -1, -1, -1)

    def of(self, costmap) -> Bounds:
        """(x0, y0, x1, y1) end-exclusive of the costmap's cells other than the value;
        (-1, -1, -1, -1) when there is none."""
        costs = np.ascontiguousarray(costmap.costs)
        log = log_of(costmap)
        if log is None or log is not self._log:
            box = other_box_within(costs, self.value, 0, 0, costs.shape[1], costs.shape[0])
        else:
            written = log.since(self._count)
            box = self._box if written is None else self._near(costs, written)
        self._log = log
        self._count = 0 if log is None else log.count
        self._box = tuple(int(v) for v in box)
        return self._box

    def _near(self, costs: np.ndarray, written: Bounds) -> Bounds:
        """The box from the last one and the box written since: every cell other than the
        value is in one of the two (those outside the written box are unchanged)."""
        x0, y0, x1, y1 = written
        old = self._box
        if old[0] >= 0:
            x0, y0 = min(x0, old[0]), min(y0, old[1])
            x1, y1 = max(x1, old[2]), max(y1, old[3])
        return other_box_within(costs, self.value, x0, y0, x1, y1)


@numba.njit(cache=True)
def _has_other(cells, value):
    """Whether the 1-D ``cells`` (a row's or a column's stretch) hold a value other than
    ``value``."""
    for cell in cells:
        if cell != value:
            return True
    return False


@numba.njit(cache=True)
def other_box_within(grid, value, x0, y0, x1, y1):
    """Cells (x0, y0, x1, y1), end-exclusive, bounding the cells of ``grid`` other than
    ``value`` inside [x0, x1) x [y0, y1), found by scanning rows, then columns, inwards
    from its edges; (-1, -1, -1, -1) when there is none. When the caller knows no such cell
    lies outside the given box, this is the box of the whole grid's such cells."""
    top = -1
    for y in range(y0, y1):
        if _has_other(grid[y, x0:x1], value):
            top = y
            break
    if top < 0:
        return -1, -1, -1, -1
    bottom = top
    for y in range(y1 - 1, top, -1):
        if _has_other(grid[y, x0:x1], value):
            bottom = y
            break
    left = x0
    while not _has_other(grid[top:bottom + 1, left], value):
        left += 1
    right = x1 - 1
    while not _has_other(grid[top:bottom + 1, right], value):
        right -= 1
    return left, top, right + 1, bottom + 1


@numba.njit(cache=True)
def equal_within(a, b, x0, y0, x1, y1):
    """Whether the 2-D grids ``a`` and ``b`` (same shape) are equal in [x0, x1) x [y0, y1)."""
    for y in range(y0, y1):
        differs = 0
        for x in range(x0, x1):
            differs |= a[y, x] ^ b[y, x]
        if differs != 0:
            return False
    return True


def warmup() -> None:
    """Compile the kernels on tiny grids."""
    grid = np.full((3, 4), 255, np.uint8)
    grid[1, 2] = 0
    other_box_within(grid, np.uint8(255), 0, 0, 4, 3)
    equal_within(grid, grid.copy(), 0, 0, 4, 3)
