"""A Costmap2DROS-like layered costmap: static + obstacle layers, inflated, at a given rate.

Two uses, as in move_base:

* the global costmap (``rolling_window: false``, ``static_map: true``): sized like the SLAM
  map it receives (resolution and origin included, as StaticLayer::matchSize), updated
  incrementally inside the bounding box of what changed (grown by the inflation radius, with
  sources up to a further radius outside, as costmap_2d's bounds logic);
* the local costmap (``rolling_window: true``): ``width`` × ``height`` m centred on the robot,
  its obstacle layer shifted with the window (Costmap2D::updateOrigin) and fully recomputed at
  each update.

Frames: every pose and point given to a costmap is in its ``global_frame`` (map for the global
costmap, odom for the local one); the navigator transforms.
"""
from __future__ import annotations

import logging
import math

import numpy as np

from slam_predict.nav import kernels
from slam_predict.nav.changes import WriteLog, known_union
from slam_predict.nav.config import CostmapConfig
from slam_predict.nav.costmap import (
    FREE,
    NO_INFORMATION,
    Bounds,
    Costmap,
    InflationLayer,
    footprint_cells,
    footprint_radii,
    grow_bounds,
    make_footprint,
    static_costs,
    union_bounds,
)

LOG = logging.getLogger(__name__)


class LayeredCostmap:
    """One costmap (global or local) built from its :class:`CostmapConfig`.

    Inputs: :meth:`set_map` (an occupancy grid with ``data`` int8 [height, width], ``origin``
    (x, y[, yaw]) m and ``resolution`` m), :meth:`add_scan` (the latest laser observation).
    :meth:`update` recomputes the master grid :attr:`costmap`; :meth:`maybe_update` does so at
    ``update_frequency``.
    """

    def __init__(self, cfg: CostmapConfig, name: str = "costmap"):
        self.cfg = cfg
        self.name = name
        self.footprint = make_footprint(cfg)
        self.inscribed_radius, self.circumscribed_radius = footprint_radii(self.footprint)
        self.default_value = NO_INFORMATION if cfg.track_unknown_space else FREE
        self.has_obstacles = bool(cfg.observation_sources.strip())
        self.uses_static = bool(cfg.static_map)
        self._map_source = None  # latest grid (for rolling windows with a static layer)
        self._static: np.ndarray | None = None
        self._raw: np.ndarray | None = None   # the map the static layer was last given
        self._raw_known: Bounds | None = None  # its box outside which it is all unknown
        self._obstacles: np.ndarray | None = None
        self._scan: tuple[np.ndarray, np.ndarray] | None = None
        self._dirty: Bounds | None = None
        self._next_update = -math.inf
        self.updates = 0
        if cfg.rolling_window or not cfg.static_map:
            nx = max(1, int(round(cfg.width / cfg.resolution)))
            ny = max(1, int(round(cfg.height / cfg.resolution)))
            self._resize(nx, ny, cfg.resolution, (cfg.origin_x, cfg.origin_y))
        else:
            self._resize(1, 1, cfg.resolution, (cfg.origin_x, cfg.origin_y))

    # ---------------------------------------------------------------------------- geometry
    def _resize(self, nx: int, ny: int, resolution: float, origin: tuple[float, float]) -> None:
        costs = np.full((ny, nx), self.default_value, np.uint8)
        self.costmap = Costmap(costs, (float(origin[0]), float(origin[1])), float(resolution),
                               WriteLog(costs))
        self.inflation = InflationLayer(self.cfg.inflation_radius, self.cfg.cost_scaling_factor,
                                        self.inscribed_radius, resolution,
                                        self.cfg.inflate_unknown)
        if self.has_obstacles:
            self._obstacles = np.full((ny, nx), self.default_value, np.uint8)
        self._static = None
        self._raw = None
        self._dirty = (0, 0, nx, ny)

    def _full(self) -> Bounds:
        return (0, 0, self.costmap.size_x, self.costmap.size_y)

    # ------------------------------------------------------------------------------ inputs
    def set_map(self, grid) -> None:
        """Receive a SLAM map (the static layer's ``map`` topic)."""
        if not self.uses_static:
            return
        data = np.asarray(grid.data)
        origin = (float(grid.origin[0]), float(grid.origin[1]))
        res = float(grid.resolution)
        self._map_source = (data, origin, res)
        if self.cfg.rolling_window:
            self._dirty = self._full()
            return
        ny, nx = data.shape
        cm = self.costmap
        if (cm.size_x, cm.size_y) != (nx, ny) or cm.origin != origin or cm.resolution != res:
            LOG.debug("%s: resized to %d x %d cells at %.3f m", self.name, nx, ny, res)
            self._resize(nx, ny, res, origin)
        known = getattr(grid, "known", None)
        if self._static is None or self._raw is None or data.dtype != self._raw.dtype:
            self._static = static_costs(data, self.cfg)
            self._raw = data.copy()
            self._raw_known = known
            self._dirty = self._full()
            return
        box = self._update_static(data, known_union(known, self._raw_known, data.shape))
        self._raw_known = known
        if box is not None:
            self._dirty = union_bounds(self._dirty, box)

    def _update_static(self, data: np.ndarray, window: Bounds | None) -> Bounds | None:
        """Re-interpret the cells of the new map ``data`` that differ from the last one (the
        interpretation is per cell, so the others keep their costs), looking only inside
        ``window`` (None: everywhere) when both maps are all unknown outside it; returns the
        box of the static costs that changed (None: none did)."""
        raw_box = changed_box(data, self._raw) if window is None else changed_within(
            data, self._raw, window)
        if raw_box is None:
            return None
        i0, j0, i1, j1 = raw_box
        self._raw[j0:j1, i0:i1] = data[j0:j1, i0:i1]
        new = static_costs(data[j0:j1, i0:i1], self.cfg)
        box = changed_box(new, self._static[j0:j1, i0:i1])
        self._static[j0:j1, i0:i1] = new
        if box is None:
            return None
        return (box[0] + i0, box[1] + j0, box[2] + i0, box[3] + j0)

    def add_scan(self, sensor_pose, points: np.ndarray) -> None:
        """Keep the latest laser observation (sensor pose (x, y, yaw) and valid endpoints (n, 2),
        in this costmap's frame); it is applied at the next update (observation_persistence 0)."""
        if self.has_obstacles:
            self._scan = (np.asarray(sensor_pose, dtype=float),
                          np.ascontiguousarray(points, dtype=float).reshape(-1, 2))

    # ------------------------------------------------------------------------------ update
    def maybe_update(self, t: float, robot_pose) -> bool:
        """Update when ``update_frequency`` says so (0 = every call); True if updated."""
        if t + 1e-9 < self._next_update:
            return False
        freq = self.cfg.update_frequency
        period = 1.0 / freq if freq > 0 else 0.0
        self._next_update = t + period if self._next_update == -math.inf else max(
            self._next_update + period, t)
        self.update(robot_pose)
        return True

    def update(self, robot_pose) -> None:
        """Recompute the master costmap around what changed (everything for a rolling window);
        the box written is recorded in the costmap's write log."""
        if self.cfg.rolling_window:
            self._update_origin(robot_pose)
            self._dirty = self._full()
        self._apply_scan()
        if self._obstacles is not None and self.cfg.footprint_clearing_enabled:
            cells = footprint_cells(self.costmap, robot_pose, self.footprint)
            if len(cells):
                self._obstacles[cells[:, 1], cells[:, 0]] = FREE
                box = (int(cells[:, 0].min()), int(cells[:, 1].min()),
                       int(cells[:, 0].max()) + 1, int(cells[:, 1].max()) + 1)
                self._dirty = union_bounds(self._dirty, box)
        self.updates += 1
        if self._dirty is None:
            return
        cm = self.costmap
        reach = min(self.inflation.cell_radius, self.inflation.effective_radius)
        box = grow_bounds(self._dirty, reach, cm.size_x, cm.size_y)
        self._dirty = None
        i0, j0, i1, j1 = box
        window = cm.costs[j0:j1, i0:i1]
        window[...] = self.default_value
        static = self._static_window(box)
        if static is not None:
            window[...] = static
        if self._obstacles is not None:
            obs = self._obstacles[j0:j1, i0:i1]
            take = (obs != NO_INFORMATION) & ((window == NO_INFORMATION) | (window < obs))
            window[take] = obs[take]
        self.inflation.apply(cm.costs, box)
        cm.log.record(box)

    def _static_window(self, box: Bounds) -> np.ndarray | None:
        i0, j0, i1, j1 = box
        if not self.uses_static:
            return None
        if not self.cfg.rolling_window:
            return None if self._static is None else self._static[j0:j1, i0:i1]
        if self._map_source is None:
            return None
        data, (mox, moy), mres = self._map_source
        wx, wy = self.costmap.map_to_world(np.arange(i0, i1), np.arange(j0, j1))
        cols = np.floor((wx - mox) / mres).astype(int)
        rows = np.floor((wy - moy) / mres).astype(int)
        inside = ((rows[:, None] >= 0) & (rows[:, None] < data.shape[0])
                  & (cols[None, :] >= 0) & (cols[None, :] < data.shape[1]))
        sampled = np.full(inside.shape, self.cfg.unknown_cost_value, dtype=np.int16)
        rr, cc = np.nonzero(inside)
        sampled[rr, cc] = data[rows[rr], cols[cc]]
        return static_costs(sampled, self.cfg)

    def _update_origin(self, robot_pose) -> None:
        """Costmap2D::updateOrigin: re-centre the window on the robot, keeping the overlap."""
        cm = self.costmap
        new_ox = float(robot_pose[0]) - cm.size_x * cm.resolution / 2.0
        new_oy = float(robot_pose[1]) - cm.size_y * cm.resolution / 2.0
        cell_ox = int((new_ox - cm.origin[0]) / cm.resolution)
        cell_oy = int((new_oy - cm.origin[1]) / cm.resolution)
        if cell_ox == 0 and cell_oy == 0:
            return
        cm.origin = (cm.origin[0] + cell_ox * cm.resolution, cm.origin[1] + cell_oy * cm.resolution)
        if self._obstacles is not None:
            self._obstacles = _shift(self._obstacles, cell_ox, cell_oy, self.default_value)

    def _apply_scan(self) -> None:
        if self._scan is None or self._obstacles is None:
            return
        sensor, points = self._scan
        self._scan = None
        cm = self.costmap
        kernels.obstacle_update(self._obstacles, cm.origin[0], cm.origin[1], cm.resolution,
                                float(sensor[0]), float(sensor[1]), points,
                                float(self.cfg.raytrace_range), float(self.cfg.obstacle_range),
                                bool(self.cfg.clearing), bool(self.cfg.marking))
        reach = max(self.cfg.raytrace_range, self.cfg.obstacle_range)
        lo = np.floor((np.array(sensor[:2]) - reach - np.array(cm.origin)) / cm.resolution)
        hi = np.ceil((np.array(sensor[:2]) + reach - np.array(cm.origin)) / cm.resolution) + 1
        box = (int(max(0, lo[0])), int(max(0, lo[1])), int(min(cm.size_x, hi[0])),
               int(min(cm.size_y, hi[1])))
        if box[0] < box[2] and box[1] < box[3]:
            self._dirty = union_bounds(self._dirty, box)

    # --------------------------------------------------------------------------- recovery
    def clear_outside(self, robot_pose, reset_distance: float, invert: bool = False) -> None:
        """ClearCostmapRecovery on the obstacle layer: reset cells outside (or, inverted,
        inside) the robot-centred square of side ``reset_distance``."""
        if self._obstacles is None:
            return
        cm = self.costmap
        half = reset_distance / 2.0
        sx = math.floor((robot_pose[0] - half - cm.origin[0]) / cm.resolution)
        sy = math.floor((robot_pose[1] - half - cm.origin[1]) / cm.resolution)
        ex = math.floor((robot_pose[0] + half - cm.origin[0]) / cm.resolution)
        ey = math.floor((robot_pose[1] + half - cm.origin[1]) / cm.resolution)
        xs = np.arange(cm.size_x)
        ys = np.arange(cm.size_y)
        inside = (((ys[:, None] > sy) & (ys[:, None] < ey))
                  & ((xs[None, :] > sx) & (xs[None, :] < ex)))
        clear = inside if invert else ~inside
        self._obstacles[clear] = self.default_value
        self._dirty = self._full()

    def reset_layers(self) -> None:
        """Costmap2DROS::resetLayers (the ~clear_costmaps service): forget every obstacle."""
        if self._obstacles is not None:
            self._obstacles[...] = self.default_value
        self._dirty = self._full()


def _shift(grid: np.ndarray, cell_ox: int, cell_oy: int, fill: int) -> np.ndarray:
    """The grid seen from an origin moved by (cell_ox, cell_oy) cells; new cells = ``fill``."""
    ny, nx = grid.shape
    out = np.full_like(grid, fill)
    src_x0, src_y0 = max(0, cell_ox), max(0, cell_oy)
    src_x1, src_y1 = min(nx, nx + cell_ox), min(ny, ny + cell_oy)
    if src_x0 < src_x1 and src_y0 < src_y1:
        out[src_y0 - cell_oy:src_y1 - cell_oy, src_x0 - cell_ox:src_x1 - cell_ox] = \
            grid[src_y0:src_y1, src_x0:src_x1]
    return out


def changed_box(new: np.ndarray, old: np.ndarray) -> Bounds | None:
    """Cells (x0, y0, x1, y1), end-exclusive, bounding where two equal-shape grids (int8 or
    uint8) differ; None when they are equal."""
    box = kernels.diff_box(np.ascontiguousarray(new), np.ascontiguousarray(old))
    return None if box[0] < 0 else tuple(int(v) for v in box)


def changed_within(new: np.ndarray, old: np.ndarray, window: Bounds) -> Bounds | None:
    """:func:`changed_box` of two equal-shape grids known to be equal outside ``window``
    (x0, y0, x1, y1), comparing only inside it."""
    x0, y0, x1, y1 = window
    if x0 >= x1 or y0 >= y1:
        return None
    box = changed_box(new[y0:y1, x0:x1], old[y0:y1, x0:x1])
    return None if box is None else (box[0] + x0, box[1] + y0, box[2] + x0, box[3] + y0)
