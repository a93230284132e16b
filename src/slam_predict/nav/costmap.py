"""costmap_2d equivalents: cost values, footprint, static/obstacle/inflation layers.

A :class:`Costmap` is a uint8 grid ``costs[my, mx]`` with the world position of the corner of
cell (0, 0) (``origin``, m) and a square ``resolution`` (m/cell), exactly as Costmap2D. Layers:

* static: a SLAM occupancy grid (int8 −1/0..100) translated by :func:`static_costs`
  (trinary: unknown → NO_INFORMATION, ≥ lethal_cost_threshold → LETHAL, else FREE);
* obstacle: LETHAL marks at laser endpoints within ``obstacle_range`` and ray-traced clearing
  within ``raytrace_range`` (:func:`slam_predict.nav.kernels.obstacle_update`);
* inflation: :class:`InflationLayer`, costmap_2d's brushfire with
  cost(d) = LETHAL at d = 0, INSCRIBED if d·res ≤ r_inscribed, else
  ⌊252·exp(−cost_scaling_factor·(d·res − r_inscribed))⌋, for d ≤ ⌈inflation_radius/res⌉ cells.

:class:`LayeredCostmap` (in :mod:`slam_predict.nav.layered`) combines them like Costmap2DROS.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from slam_predict.nav import kernels
from slam_predict.nav.changes import WriteLog
from slam_predict.nav.config import CostmapConfig

FREE = kernels.FREE
INSCRIBED = kernels.INSCRIBED
LETHAL = kernels.LETHAL
NO_INFORMATION = kernels.NO_INFORMATION

Bounds = tuple[int, int, int, int]  # (min_i, min_j, max_i, max_j), max exclusive, in cells


@dataclass
class Costmap:
    """A grid of costs: ``costs[my, mx]`` uint8, ``origin`` = world (x, y) of cell (0, 0)'s
    lower-left corner (m), ``resolution`` m/cell; ``log``: the boxes written into ``costs``
    when its one writer records them (a layered costmap's), else None."""

    costs: np.ndarray
    origin: tuple[float, float]
    resolution: float
    log: WriteLog | None = field(default=None, repr=False, compare=False)

    @property
    def size_x(self) -> int:
        """Cells along x."""
        return int(self.costs.shape[1])

    @property
    def size_y(self) -> int:
        """Cells along y."""
        return int(self.costs.shape[0])

    def world_to_map(self, x: float, y: float) -> tuple[int, int] | None:
        """Cell (mx, my) holding world point (x, y), or None outside (Costmap2D::worldToMap)."""
        ox, oy = self.origin
        if x < ox or y < oy:
            return None
        mx = int((x - ox) / self.resolution)
        my = int((y - oy) / self.resolution)
        if mx < self.size_x and my < self.size_y:
            return mx, my
        return None

    def map_to_world(self, mx, my) -> tuple[np.ndarray, np.ndarray]:
        """World coordinates (m) of cell centres."""
        return (self.origin[0] + (np.asarray(mx) + 0.5) * self.resolution,
                self.origin[1] + (np.asarray(my) + 0.5) * self.resolution)

    def copy(self) -> Costmap:
        """An independent copy (without a write log)."""
        return Costmap(self.costs.copy(), self.origin, self.resolution)


# ------------------------------------------------------------------------------- footprint
def make_footprint(cfg: CostmapConfig) -> np.ndarray:
    """The padded footprint polygon (k, 2) in the robot frame (costmap_2d footprint.cpp).

    An empty ``footprint`` gives a 16-gon of ``robot_radius``; padding moves every vertex
    away from the axes by ``footprint_padding`` (padFootprint).
    """
    if cfg.footprint:
        points = np.asarray(cfg.footprint, dtype=float)
    else:
        angles = np.arange(16) * 2.0 * math.pi / 16
        points = cfg.robot_radius * np.stack([np.cos(angles), np.sin(angles)], axis=1)
    pad = cfg.footprint_padding
    return points + np.sign(points) * pad


def footprint_radii(footprint: np.ndarray) -> tuple[float, float]:
    """(inscribed, circumscribed) radius of a polygon about the robot centre, m."""
    k = len(footprint)
    circumscribed = float(np.max(np.hypot(footprint[:, 0], footprint[:, 1])))
    inscribed = math.inf
    for i in range(k):
        a = footprint[i]
        b = footprint[(i + 1) % k]
        inscribed = min(inscribed, _point_segment_distance(np.zeros(2), a, b))
    return float(inscribed), circumscribed


def inscribed_radius(cfg: CostmapConfig) -> float:
    """Inscribed radius (m) of the padded footprint of ``cfg``: the clearance the costmaps give
    the robot centre (cells nearer an obstacle are INSCRIBED, never planned through)."""
    return footprint_radii(make_footprint(cfg))[0]


def _point_segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    ab = b - a
    denom = float(ab @ ab)
    t = 0.0 if denom == 0 else min(1.0, max(0.0, float((p - a) @ ab) / denom))
    return float(np.hypot(*(a + t * ab - p)))


_YAW_BINS = 72
_FOOTPRINT_CACHE: dict = {}


def footprint_cells(costmap: Costmap, pose, footprint: np.ndarray) -> np.ndarray:
    """(n, 2) cells (mx, my) covered by the footprint at ``pose``: cells whose centre is inside
    the polygon grown by half a cell, with the robot taken at the centre of its cell and its yaw
    rounded to 5° (cached offsets; these are the robot's own cells, not a collision test)."""
    cell = costmap.world_to_map(float(pose[0]), float(pose[1]))
    if cell is None:
        return np.empty((0, 2), dtype=np.int64)
    k = int(round(float(pose[2]) / (2 * math.pi / _YAW_BINS))) % _YAW_BINS
    key = (costmap.resolution, k, footprint.tobytes())
    offsets = _FOOTPRINT_CACHE.get(key)
    if offsets is None:
        offsets = _footprint_offsets(footprint, k * 2 * math.pi / _YAW_BINS, costmap.resolution)
        _FOOTPRINT_CACHE[key] = offsets
    cells = offsets + np.array(cell)
    keep = ((cells[:, 0] >= 0) & (cells[:, 0] < costmap.size_x) & (cells[:, 1] >= 0)
            & (cells[:, 1] < costmap.size_y))
    return cells[keep]


def _footprint_offsets(footprint: np.ndarray, yaw: float, res: float) -> np.ndarray:
    """Cell offsets covered by the footprint rotated by ``yaw`` about a cell centre."""
    c, s = math.cos(yaw), math.sin(yaw)
    poly = np.stack([footprint[:, 0] * c - footprint[:, 1] * s,
                     footprint[:, 0] * s + footprint[:, 1] * c], axis=1)
    reach = int(math.ceil(np.abs(poly).max() / res)) + 1
    gx, gy = np.meshgrid(np.arange(-reach, reach + 1), np.arange(-reach, reach + 1))
    inside = _inside_convex(poly, gx.ravel() * res, gy.ravel() * res, res / 2.0)
    return np.stack([gx.ravel()[inside], gy.ravel()[inside]], axis=1).astype(np.int64)


def _inside_convex(poly: np.ndarray, px: np.ndarray, py: np.ndarray, margin: float) -> np.ndarray:
    """Points inside a convex polygon grown by ``margin`` (either vertex order)."""
    k = len(poly)
    signs = []
    for i in range(k):
        a = poly[i]
        b = poly[(i + 1) % k]
        edge = b - a
        length = math.hypot(*edge) or 1.0
        signs.append((edge[0] * (py - a[1]) - edge[1] * (px - a[0])) / length)
    signs = np.array(signs)
    return np.all(signs >= -margin, axis=0) | np.all(signs <= margin, axis=0)


# ------------------------------------------------------------------------------ static layer
def static_costs(data: np.ndarray, cfg: CostmapConfig) -> np.ndarray:
    """StaticLayer::interpretValue of an int8 occupancy grid (uint8 costs, same shape); an
    int8 grid is mapped through the table of its 256 possible values."""
    data = np.asarray(data)
    if data.dtype == np.int8:
        table = _interpret_values(np.arange(256, dtype=np.uint8).view(np.int8), cfg)
        return table[data.view(np.uint8)]
    return _interpret_values(data, cfg)


def _interpret_values(data: np.ndarray, cfg: CostmapConfig) -> np.ndarray:
    """StaticLayer::interpretValue, value by value (uint8 costs, same shape)."""
    values = np.asarray(data).astype(np.int16)
    unknown = values == cfg.unknown_cost_value
    lethal = values >= cfg.lethal_cost_threshold
    if cfg.trinary_costmap:
        out = np.zeros(values.shape, np.uint8)
    else:
        scaled = np.clip(values, 0, None) / float(cfg.lethal_cost_threshold) * LETHAL
        out = scaled.astype(np.uint8)
    out[lethal] = LETHAL
    out[unknown] = NO_INFORMATION if cfg.track_unknown_space else FREE
    return out


# --------------------------------------------------------------------------- inflation layer
class InflationLayer:
    """costmap_2d's InflationLayer for one footprint and resolution.

    Args:
        inflation_radius: m; cells up to ⌈radius/res⌉ cells from a LETHAL cell get a cost.
        cost_scaling_factor: the exponential decay rate, 1/m.
        inscribed_radius: m (from the footprint).
        resolution: m/cell.
        inflate_unknown: let unknown cells take any inflated cost (not only ≥ INSCRIBED).
    """

    def __init__(self, inflation_radius: float, cost_scaling_factor: float,
                 inscribed_radius: float, resolution: float, inflate_unknown: bool = False):
        self.inflation_radius = float(inflation_radius)
        self.weight = float(cost_scaling_factor)
        self.inscribed_radius = float(inscribed_radius)
        self.resolution = float(resolution)
        self.inflate_unknown = bool(inflate_unknown)
        self.cell_radius = int(max(0.0, math.ceil(self.inflation_radius / self.resolution)))
        n = self.cell_radius + 2
        ii, jj = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
        self.dist_cache = np.hypot(ii, jj)
        self.cost_cache = np.vectorize(self.compute_cost, otypes=[np.uint8])(self.dist_cache)
        uniq, inverse = np.unique(self.dist_cache, return_inverse=True)
        self.bin_of = inverse.reshape(self.dist_cache.shape).astype(np.int64)
        self.nbins = int(len(uniq))
        nonzero = self.dist_cache[self.cost_cache > FREE]
        self.effective_radius = int(math.ceil(nonzero.max())) if nonzero.size else 0
        self._pool = _pool(16)

    def compute_cost(self, distance: float) -> int:
        """Cost of a cell ``distance`` cells from the nearest LETHAL cell (computeCost)."""
        if distance == 0:
            return LETHAL
        if distance * self.resolution <= self.inscribed_radius:
            return INSCRIBED
        factor = math.exp(-self.weight * (distance * self.resolution - self.inscribed_radius))
        return int((INSCRIBED - 1) * factor)

    def apply(self, master: np.ndarray, bounds: Bounds | None = None) -> None:
        """Inflate ``master`` (uint8 [ny, nx]) in place within ``bounds`` (default: all)."""
        if self.cell_radius == 0:
            return
        ny, nx = master.shape
        min_i, min_j, max_i, max_j = bounds if bounds is not None else (0, 0, nx, ny)
        if min_i >= max_i or min_j >= max_j:
            return
        saved = master[min_j:max_j, min_i:max_i].copy()
        r = min(self.cell_radius, self.effective_radius)
        reach = (min(nx, max_i + 2 * r) - max(0, min_i - 2 * r)) * \
            (min(ny, max_j + 2 * r) - max(0, min_j - 2 * r))
        need = 5 * reach  # hard bound: sources + 4 entries per reached cell
        if len(self._pool[0]) < min(need, 1 << 20):
            self._pool = _pool(min(need, 1 << 20))
        while True:
            used = kernels.inflate(master, int(min_i), int(min_j), int(max_i), int(max_j), r,
                                   self.cost_cache, self.dist_cache, self.bin_of, self.nbins,
                                   self.inflate_unknown, *self._pool)
            if used >= 0:
                return
            master[min_j:max_j, min_i:max_i] = saved
            self._pool = _pool(min(need, 2 * len(self._pool[0])))


def _pool(size: int):
    """Work arrays of the inflation queue."""
    return tuple(np.empty(max(int(size), 16), np.int32) for _ in range(3))


def union_bounds(a: Bounds | None, b: Bounds | None) -> Bounds | None:
    """Smallest box holding both (None = empty)."""
    if a is None:
        return b
    if b is None:
        return a
    return (min(a[0], b[0]), min(a[1], b[1]), max(a[2], b[2]), max(a[3], b[3]))


def grow_bounds(b: Bounds | None, cells: int, size_x: int, size_y: int) -> Bounds | None:
    """``b`` grown by ``cells`` on every side, clipped to the grid."""
    if b is None:
        return None
    return (max(0, b[0] - cells), max(0, b[1] - cells), min(size_x, b[2] + cells),
            min(size_y, b[3] + cells))
