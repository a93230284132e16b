"""The published occupancy grid, rebuilt as slam_gmapping's updateMap does.

A fresh map of the current bounds (initially xmin..xmax, ymin..ymax) is built by re-registering
every node of the best particle's trajectory, newest first, with free-space tracing
(:mod:`.raytrace`); the map grows by enlargeStep beyond scans that leave it, and the grown bounds
are kept for the next rebuild. Cells: −1 never seen, 100 when hits/visits > occ_thresh, else 0.
The grid spans the whole map (default 4000 x 4000 cells); ``origin`` is GMapping's world position
of cell (0, 0) — its centre in GMapping's own convention, which slam_gmapping publishes as the
ROS origin (so ROS tools see the map shifted by half a cell, exactly as with the real node).
"""
from __future__ import annotations

from typing import Optional, Tuple

import numpy as np

from slam_predict.slam import OccupancyGrid
from slam_predict.slam.gmapping import kernels, raytrace
from slam_predict.slam.gmapping.maps import Geometry
from slam_predict.slam.gmapping.params import GMappingParams


class MapBuilder:
    """Rebuilds the published map from laser poses and readings; keeps the grown bounds."""

    def __init__(self, params: GMappingParams, angles: np.ndarray):
        if params.maxRange is None or params.maxUrange is None:
            raise ValueError("maxRange/maxUrange must be resolved (params.with_ranges)")
        self.params = params
        angles = np.asarray(angles, dtype=float)
        self.ca = np.cos(angles)
        self.sa = np.sin(angles)
        self.bounds = (params.xmin, params.ymin, params.xmax, params.ymax)
        self._published_size: Tuple[int, int] = (0, 0)

    def geometry(self, poses: np.ndarray, readings: np.ndarray,
                 start: Optional[Geometry] = None) -> Geometry:
        """The map geometry after registering the scans in order (growing as needed), starting
        from ``start`` or from the current bounds."""
        p = self.params
        geometry = Geometry.bounded(*self.bounds, p.delta) if start is None else start.copy()
        for pose, ranges in zip(poses, readings):
            bounds = kernels.scan_bounds(float(pose[0]), float(pose[1]), float(pose[2]), ranges,
                                         self.ca, self.sa, p.maxRange, p.maxUrange)
            geometry.grow_to(bounds)
        return geometry

    def counts(self, geometry: Geometry, poses: np.ndarray, readings: np.ndarray):
        """(x0, y0, hits, visits): counts (w, h) over the window of touched cells at (x0, y0)."""
        p = self.params
        g = geometry
        args = (self.ca, self.sa, p.maxRange, p.maxUrange, g.sx2, g.sy2, g.cx, g.cy, g.delta)
        lo_x, lo_y, hi_x, hi_y = raytrace.touched_cells(poses, readings, *args)
        width, height = g.size
        lo_x, lo_y = max(lo_x, 0), max(lo_y, 0)
        hi_x, hi_y = min(hi_x, width - 1), min(hi_y, height - 1)
        if hi_x < lo_x or hi_y < lo_y:
            empty = np.zeros((0, 0), dtype=np.int32)
            return 0, 0, empty, empty
        hits, visits = raytrace.count_scans(poses, readings, *args, lo_x, lo_y,
                                            hi_x - lo_x + 1, hi_y - lo_y + 1)
        return lo_x, lo_y, hits, visits

    def build(self, poses: np.ndarray, readings: np.ndarray) -> OccupancyGrid:
        """The grid from laser poses (K, 3) and readings (K, B), newest first."""
        poses, readings = self._arrays(poses, readings)
        geometry = self.geometry(poses, readings)
        width, height = geometry.size
        if (width, height) != self._published_size:
            xmin, ymin = geometry.cell_to_world(0, 0)
            xmax, ymax = geometry.cell_to_world(width, height)
            self.bounds = (xmin, ymin, xmax, ymax)
            self._published_size = (width, height)
        return self.render(geometry, poses, readings)

    def _arrays(self, poses, readings):
        poses = np.ascontiguousarray(poses, dtype=float).reshape(-1, 3)
        readings = np.ascontiguousarray(readings, dtype=float).reshape(len(poses), len(self.ca))
        return poses, readings

    def render(self, geometry: Geometry, poses: np.ndarray, readings: np.ndarray) -> OccupancyGrid:
        """The grid of the scans on a given geometry (which must already contain them)."""
        poses, readings = self._arrays(poses, readings)
        width, height = geometry.size
        x0, y0, hits, visits = self.counts(geometry, poses, readings)
        data = np.full((height, width), -1, dtype=np.int8)
        if hits.size:
            values = raytrace.occupancy_values(hits, visits, self.params.occ_thresh)
            data[y0:y0 + values.shape[1], x0:x0 + values.shape[0]] = values.T
        return OccupancyGrid(data, self.params.delta, geometry.cell_to_world(0, 0))

    def empty(self) -> OccupancyGrid:
        """An all-unknown grid of the current bounds."""
        geometry = Geometry.bounded(*self.bounds, self.params.delta)
        width, height = geometry.size
        return OccupancyGrid(np.full((height, width), -1, dtype=np.int8), self.params.delta,
                             geometry.cell_to_world(0, 0))
