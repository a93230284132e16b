"""Frontiers on a SLAM occupancy grid: free cells (0) with an unknown (−1) 4-neighbour,
grouped into 8-connected clusters; clusters shorter than ``min_frontier_size`` (cells × m/cell,
explore_lite's measure) are dropped.

Each :class:`Frontier` has its cells (world m), size, centroid, a goal point — the frontier cell
nearest the centroid, a known free cell where a centroid may fall in a wall — and
``min_distance``, the Euclidean distance (m) from the robot to its nearest cell.

Extension (``min_unknown_width`` > 0; 0, explore_lite's rule, by default): only unknown space
with room in it makes a frontier. Unknown cells count only when they are 4-connected, through
unknown cells, to a square of unknown cells ``min_unknown_width`` m on a side (cells outside
the grid count as unknown). Beams grazing a long wall mark cells inside the wall free and leave
unknown slivers 1–2 cells wide between its two occupied faces: frontiers no pose can ever
observe, always nearer than the real ones (office_800: 27 goals in 630 s to such slivers while
three real frontiers stayed unvisited). A real frontier borders a room, a corridor or the
outside, which all hold such a square.
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from slam_predict.explore import kernels as frontier_kernels
from slam_predict.nav import kernels
from slam_predict.nav.changes import known_union
from slam_predict.nav.layered import changed_box, changed_within


@dataclass
class Frontier:
    """A cluster of frontier cells; positions in the grid's frame (m)."""

    cells: np.ndarray
    size: int
    centroid: np.ndarray
    goal: np.ndarray
    min_distance: float

    def length(self, resolution: float) -> float:
        """explore_lite's frontier size in m (cells × resolution)."""
        return self.size * resolution


def frontier_mask(data: np.ndarray, min_unknown_width: int = 0) -> np.ndarray:
    """Free cells with at least one unknown 4-neighbour (bool, same shape); with
    ``min_unknown_width`` (cells) > 1, only unknown cells joined to an unknown square of that
    side count (:func:`roomy_unknown`). One numba pass
    (:func:`slam_predict.explore.kernels.frontier_cells`)."""
    return frontier_kernels.frontier_cells(np.ascontiguousarray(data, dtype=np.int8),
                                           int(min_unknown_width))


def roomy_unknown(unknown: np.ndarray, width: int) -> np.ndarray:
    """The cells of ``unknown`` (bool) 4-connected, through ``unknown`` cells, to a
    ``width`` × ``width`` square of unknown cells; cells beyond the array count as unknown.
    ``width`` <= 1 returns a copy of ``unknown``."""
    return frontier_kernels.roomy_unknown(np.ascontiguousarray(unknown, dtype=bool), int(width))


def known_box(data: np.ndarray, grow: int = 1):
    """(r0, r1, c0, c1) of the known cells grown by ``grow`` cells, or None when all is
    unknown."""
    if data.dtype == np.int8:     # one pass, no temporary
        c0, r0, c1, r1 = (int(v) for v in kernels.other_box(np.ascontiguousarray(data),
                                                             np.int8(-1)))
        if c0 < 0:
            return None
    else:
        known = data != -1
        rows = np.nonzero(known.any(axis=1))[0]
        if len(rows) == 0:
            return None
        cols = np.nonzero(known.any(axis=0))[0]
        r0, r1, c0, c1 = int(rows[0]), int(rows[-1]) + 1, int(cols[0]), int(cols[-1]) + 1
    return (max(0, r0 - grow), min(data.shape[0], r1 + grow),
            max(0, c0 - grow), min(data.shape[1], c1 + grow))


@dataclass(frozen=True)
class Cluster:
    """A frontier cluster as the map alone gives it (world m): its cells, size, centroid and
    goal cell (the cell nearest the centroid)."""

    cells: np.ndarray
    size: int
    centroid: np.ndarray
    goal: np.ndarray


def frontier_clusters(grid, min_frontier_size: float,
                      min_unknown_width: float = 0.0) -> list[Cluster]:
    """The frontier clusters of ``grid`` (data, origin, resolution) in label order, those
    shorter than ``min_frontier_size`` m dropped; ``min_unknown_width`` (m): see the module
    docstring (0 = explore_lite)."""
    data = np.asarray(grid.data)
    res = float(grid.resolution)
    width = int(round(min_unknown_width / res)) if min_unknown_width > 0 else 0
    box = known_box(data, 1 + width)   # room for the unknown squares along the known edge
    if box is None:
        return []
    r0, r1, c0, c1 = box
    mask = frontier_mask(data[r0:r1, c0:c1], width)
    # 8-connected clusters in ndimage.label's order, cells in raster order within each
    rows, cols, starts = frontier_kernels.clusters_in_raster_order(mask)
    ox, oy = float(grid.origin[0]), float(grid.origin[1])
    xs = ox + (cols + c0 + 0.5) * res
    ys = oy + (rows + r0 + 0.5) * res
    out: list[Cluster] = []
    for a, b in zip(starts[:-1], starts[1:], strict=True):
        if (b - a) * res < min_frontier_size:
            continue
        cells = np.stack([xs[a:b], ys[a:b]], axis=1)
        centroid = cells.mean(axis=0)
        goal = cells[int(np.argmin(np.hypot(*(cells - centroid).T)))]
        out.append(Cluster(cells, int(b - a), centroid, goal))
    return out


def find_frontiers(grid, robot_xy: Sequence[float], min_frontier_size: float,
                   min_unknown_width: float = 0.0,
                   clusters: list[Cluster] | None = None) -> list[Frontier]:
    """Frontier clusters of ``grid`` (data, origin, resolution) sorted by ``min_distance``;
    ``min_unknown_width`` (m): see the module docstring (0 = explore_lite). ``clusters``: the
    grid's :func:`frontier_clusters` when already known (e.g. from a :class:`ClusterCache`)."""
    if clusters is None:
        clusters = frontier_clusters(grid, min_frontier_size, min_unknown_width)
    rx, ry = float(robot_xy[0]), float(robot_xy[1])
    out = [Frontier(c.cells, c.size, c.centroid, c.goal,
                    float(np.min(np.hypot(c.cells[:, 0] - rx, c.cells[:, 1] - ry))))
           for c in clusters]
    out.sort(key=lambda f: f.min_distance)
    return out


class ClusterCache:
    """:func:`frontier_clusters` of the last grid asked for: a grid with the same cells,
    origin and resolution (and the same two sizes) gets the same clusters without a new search.
    The SLAM map is republished every few seconds while the explorer looks at it every second,
    so most searches are of an unchanged map. The cells are compared, not the grid objects, so
    a grid changed in place is searched again."""

    def __init__(self):
        self._key: tuple | None = None
        self._data = np.empty(0, np.int8)
        self._known = None                     # _data's box outside which it is all unknown
        self._clusters: list[Cluster] = []
        self._component: tuple | None = None   # (free component mask, row0, col0) of _data

    def clusters(self, grid, min_frontier_size: float,
                 min_unknown_width: float = 0.0) -> list[Cluster]:
        data = np.asarray(grid.data)
        key = (float(grid.origin[0]), float(grid.origin[1]), float(grid.resolution),
               float(min_frontier_size), float(min_unknown_width), data.shape, data.dtype.str)
        known = getattr(grid, "known", None)
        if key != self._key or not self._same_map(data, known):
            self._clusters = frontier_clusters(grid, min_frontier_size, min_unknown_width)
            self._key, self._data, self._known = key, data.copy(), known
            self._component = None
        return self._clusters

    def _same_map(self, data: np.ndarray, known) -> bool:
        """Whether ``data`` (of the last map's shape and dtype) holds the last map's cells,
        compared only inside the box outside which both are all unknown when the two grids
        tell one (``known``), else whole."""
        window = known_union(known, self._known, data.shape)
        if window is None or data.dtype != np.int8:
            return _same_cells(data, self._data)
        return changed_within(data, self._data, window) is None

    def reachable(self, grid, robot_xy: Sequence[float]) -> list[Cluster]:
        """The clusters of the last :meth:`clusters` call that have a cell in the free space
        4-connected to the robot's cell (x, y m), as explore_lite's frontier search finds them
        (:func:`~slam_predict.explore.kernels.free_component`): frontier cells in free pockets
        a wall line cuts off, such as the strips GMapping draws inside a thick wall seen from two
        poses, are none. The component is searched again when the map changed or the robot's
        cell is not in it."""
        res = float(grid.resolution)
        row = int(np.floor((float(robot_xy[1]) - float(grid.origin[1])) / res))
        col = int(np.floor((float(robot_xy[0]) - float(grid.origin[0])) / res))
        if self._component is None or not _inside(self._component, row, col):
            box = known_box(self._data, 1)
            if box is None:
                return []
            r0, r1, c0, c1 = box
            mask = frontier_kernels.free_component(
                np.ascontiguousarray(self._data[r0:r1, c0:c1]),
                min(max(row, r0), r1 - 1) - r0, min(max(col, c0), c1 - 1) - c0)
            self._component = (mask, r0, c0)
        mask, r0, c0 = self._component
        ox, oy = float(grid.origin[0]), float(grid.origin[1])
        return [c for c in self._clusters
                if mask[np.floor((c.cells[:, 1] - oy) / res).astype(int) - r0,
                        np.floor((c.cells[:, 0] - ox) / res).astype(int) - c0].any()]


def _inside(component: tuple, row: int, col: int) -> bool:
    """Whether grid cell (row, col) is in ``component`` (mask, row0, col0)."""
    mask, r0, c0 = component
    r, c = row - r0, col - c0
    return 0 <= r < mask.shape[0] and 0 <= c < mask.shape[1] and bool(mask[r, c])


def _same_cells(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether two grids of one shape and dtype hold the same cells (an int8 or uint8 grid is
    compared in one pass, without a temporary)."""
    if a.dtype in (np.int8, np.uint8):
        return changed_box(a, b) is None
    return bool(np.array_equal(a, b))


def clear_goal(frontier: Frontier, grid, clearance: float, search: float = 1.0) -> np.ndarray:
    """A goal point for ``frontier`` away from walls, so the robot is not sent into a spot it
    cannot turn in: the known free cell nearest the frontier's reference cell (``goal``) among
    the frontier cells and the free cells within ``search`` m of it that are at least
    ``clearance`` m from every occupied cell of ``grid`` and joined to a frontier cell by a
    path of at most ``search`` m (8-connected steps) over known free cells, so the goal is
    never across a wall from its frontier; when there is none, the frontier cell with the most
    clearance. ``clearance`` 0 returns ``frontier.goal``."""
    if clearance <= 0:
        return frontier.goal
    data = np.asarray(grid.data)
    res = float(grid.resolution)
    ox, oy = float(grid.origin[0]), float(grid.origin[1])
    cols = np.floor((frontier.cells[:, 0] - ox) / res).astype(int)
    rows = np.floor((frontier.cells[:, 1] - oy) / res).astype(int)
    pad = int(np.ceil((clearance + search) / res)) + 1
    r0, c0 = max(0, rows.min() - pad), max(0, cols.min() - pad)
    r1, c1 = min(data.shape[0], rows.max() + pad + 1), min(data.shape[1], cols.max() + pad + 1)
    window = data[r0:r1, c0:c1]
    free_of_walls = window != 100
    dist = (np.full(window.shape, np.inf) if free_of_walls.all()
            else ndimage.distance_transform_edt(free_of_walls) * res)
    ok = (window == 0) & (dist >= clearance) & _free_within(window == 0, rows - r0, cols - c0,
                                                            int(np.ceil(search / res)))
    if not ok.any():
        return frontier.cells[int(np.argmax(dist[rows - r0, cols - c0]))]
    rr, cc = np.nonzero(ok)
    xs = ox + (cc + c0 + 0.5) * res
    ys = oy + (rr + r0 + 0.5) * res
    gap = np.hypot(xs - frontier.goal[0], ys - frontier.goal[1])
    k = int(np.argmin(gap))
    if gap[k] > search + res:
        return frontier.cells[int(np.argmax(dist[rows - r0, cols - c0]))]
    return np.array([xs[k], ys[k]])


def _free_within(free: np.ndarray, rows: np.ndarray, cols: np.ndarray, steps: int) -> np.ndarray:
    """Cells of ``free`` reached from the seed cells (rows, cols) in at most ``steps``
    8-connected steps over ``free`` cells (the seeds count when they are free)."""
    reached = np.zeros(free.shape, bool)
    reached[rows, cols] = True
    reached &= free
    struct = np.ones((3, 3), bool)
    for _ in range(steps):
        grown = ndimage.binary_dilation(reached, struct) & free
        if np.array_equal(grown, reached):
            break
        reached = grown
    return reached


def nearest_cell_beyond(frontier: Frontier, robot_pose, distance: float) -> np.ndarray:
    """The frontier's cell nearest the robot (x, y, …) at least ``distance`` m away; its
    farthest cell when none is."""
    dist = np.hypot(*(frontier.cells - np.asarray(robot_pose[:2])).T)
    far = dist >= distance
    if not far.any():
        return frontier.cells[int(np.argmax(dist))]
    return frontier.cells[np.flatnonzero(far)[int(np.argmin(dist[far]))]]
