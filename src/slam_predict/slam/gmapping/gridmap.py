"""The published occupancy grid, rebuilt as slam_gmapping's updateMap does.

A fresh map of the current bounds (initially xmin..xmax, ymin..ymax) is built by re-registering
every node of the best particle's trajectory, newest first, with free-space tracing
(:mod:`.raytrace`); the map grows by enlargeStep beyond scans that leave it, and the grown bounds
are kept for the next rebuild. Cells: −1 never seen, 100 when hits/visits > occ_thresh, else 0.
The grid spans the whole map (default 4000 x 4000 cells); ``origin`` is GMapping's world position
of cell (0, 0) — its centre in GMapping's own convention, which slam_gmapping publishes as the
ROS origin (so ROS tools see the map shifted by half a cell, exactly as with the real node).

:class:`IncrementalMap` gives the same grid without re-tracing the whole trajectory at every
update: it keeps the counts of the trajectory it saw last and only removes / adds the scans in
which the new trajectory differs (issue #7: the full rebuild grew with the run).
"""
from __future__ import annotations

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
        self._published_size: tuple[int, int] = (0, 0)

    def geometry(self, poses: np.ndarray, readings: np.ndarray,
                 start: Geometry | None = None) -> Geometry:
        """The map geometry after registering the scans in order (growing as needed), starting
        from ``start`` or from the current bounds."""
        p = self.params
        poses, readings = self._arrays(poses, readings)
        geometry = Geometry.bounded(*self.bounds, p.delta) if start is None else start.copy()
        bounds = kernels.scans_bounds(poses, readings, self.ca, self.sa, p.maxRange, p.maxUrange)
        return grow_geometry(geometry, bounds)

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
        self.publish_size(geometry)
        return self.render(geometry, poses, readings)

    def publish_size(self, geometry: Geometry) -> None:
        """Keep the bounds of a published geometry whose size changed (for the next build)."""
        width, height = geometry.size
        if (width, height) != self._published_size:
            xmin, ymin = geometry.cell_to_world(0, 0)
            xmax, ymax = geometry.cell_to_world(width, height)
            self.bounds = (xmin, ymin, xmax, ymax)
            self._published_size = (width, height)

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


def grow_geometry(geometry: Geometry, bounds: np.ndarray) -> Geometry:
    """``geometry`` grown (in place) by every row (xmin, ymin, xmax, ymax) of ``bounds`` in
    order, exactly as calling :meth:`Geometry.grow_to` row by row; returns it."""
    bounds = np.ascontiguousarray(bounds, dtype=float).reshape(-1, 4)
    k = 0
    while True:
        g = geometry
        k = kernels.first_outside(bounds, k, g.cx, g.cy, g.delta, g.sx2, g.sy2, g.nx, g.ny)
        if k < 0:
            return geometry
        geometry.grow_to(tuple(float(v) for v in bounds[k]))
        k += 1


class IncrementalMap:
    """The published map of :class:`MapBuilder`, kept up to date along a trajectory.

    Hit and visit counts of the scans integrated so far are cached in cells relative to the map
    centre of the builder's bounds. A new trajectory (oldest first) is compared with the cached
    one: the nodes after their longest common prefix are removed from the counts and the new
    ones added (counts are sums, so the order does not matter). The geometry is regrown from
    the cached per-scan bounds, newest first, as :meth:`MapBuilder.build` grows it. The result
    equals ``builder.build`` of the same scans cell for cell; a change of the bounds' centre
    (after the map grew) restarts from empty counts.
    """

    def __init__(self, builder: MapBuilder):
        self.builder = builder
        self.stats = {"added": 0, "removed": 0, "restarts": 0}
        self._restart(None)

    def _restart(self, frame) -> None:
        self.frame = frame
        self.scans = np.zeros(0, dtype=np.int64)
        self.poses = np.zeros((0, 3))
        self.bounds = np.zeros((0, 4))
        self.readings: list = []
        self.corner = (0, 0)  # frame cell of counts[0, 0]
        self.hits = np.zeros((0, 0), dtype=np.int32)
        self.visits = np.zeros((0, 0), dtype=np.int32)

    def build(self, scans: np.ndarray, poses: np.ndarray, reading_of) -> OccupancyGrid:
        """The grid of laser poses (K, 3) of processed scans ``scans`` (K,), oldest first;
        ``reading_of(scan)`` gives a scan's ranges (B,)."""
        b = self.builder
        scans = np.asarray(scans, dtype=np.int64).reshape(-1)
        poses = np.ascontiguousarray(poses, dtype=float).reshape(-1, 3)
        base = Geometry.bounded(*b.bounds, b.params.delta)
        if self.frame != (base.cx, base.cy):
            self.stats["restarts"] += 1
            self._restart((base.cx, base.cy))
        keep = self._common_prefix(scans, poses)
        if keep < len(self.scans):
            self._count(self.poses[keep:], np.array(self.readings[keep:]), -1)
            self.stats["removed"] += len(self.scans) - keep
        readings = [reading_of(int(k)) for k in scans[keep:]]
        new = np.array(readings, dtype=float).reshape(len(readings), len(b.ca))
        self._count(poses[keep:], new, 1)
        self.stats["added"] += len(new)
        p = b.params
        self.bounds = np.concatenate([self.bounds[:keep], kernels.scans_bounds(
            poses[keep:], new, b.ca, b.sa, p.maxRange, p.maxUrange)])
        self.scans, self.poses = scans.copy(), poses.copy()
        self.readings = self.readings[:keep] + readings
        geometry = grow_geometry(base, self.bounds[::-1])
        b.publish_size(geometry)
        return self._render(geometry)

    def _common_prefix(self, scans: np.ndarray, poses: np.ndarray) -> int:
        n = min(len(scans), len(self.scans))
        same = (scans[:n] == self.scans[:n]) & np.all(poses[:n] == self.poses[:n], axis=1)
        return n if same.all() else int(np.argmin(same))

    def _count(self, poses: np.ndarray, readings: np.ndarray, sign: int) -> None:
        """Add (sign 1) or remove (−1) scans in the centre-relative frame (sx2 = sy2 = 0)."""
        if not len(poses):
            return
        b, p = self.builder, self.builder.params
        cx, cy = self.frame
        args = (b.ca, b.sa, p.maxRange, p.maxUrange, 0, 0, cx, cy, p.delta)
        lo_x, lo_y, hi_x, hi_y = raytrace.touched_cells(poses, readings, *args)
        if hi_x < lo_x:
            return
        self._cover(lo_x, lo_y, hi_x, hi_y)
        raytrace.add_scans(self.hits, self.visits, poses, readings, *args, *self.corner, sign)

    def _cover(self, lo_x: int, lo_y: int, hi_x: int, hi_y: int) -> None:
        """Enlarge the count arrays to cover frame cells lo..hi (inclusive)."""
        (x0, y0), (w, h) = self.corner, self.hits.shape
        if w and x0 <= lo_x and y0 <= lo_y and hi_x < x0 + w and hi_y < y0 + h:
            return
        if w:
            lo_x, lo_y = min(lo_x, x0), min(lo_y, y0)
            hi_x, hi_y = max(hi_x, x0 + w - 1), max(hi_y, y0 + h - 1)
        hits = np.zeros((hi_x - lo_x + 1, hi_y - lo_y + 1), dtype=np.int32)
        visits = np.zeros_like(hits)
        hits[x0 - lo_x:x0 - lo_x + w, y0 - lo_y:y0 - lo_y + h] = self.hits
        visits[x0 - lo_x:x0 - lo_x + w, y0 - lo_y:y0 - lo_y + h] = self.visits
        self.hits, self.visits, self.corner = hits, visits, (lo_x, lo_y)

    def _render(self, geometry: Geometry) -> OccupancyGrid:
        """The grid of the counts (−1 outside their window, whose box is ``known``)."""
        width, height = geometry.size
        data = np.full((height, width), -1, dtype=np.int8)
        known = (0, 0, 0, 0)
        if self.hits.size:
            x0, y0 = self.corner[0] + geometry.sx2, self.corner[1] + geometry.sy2
            w, h = self.hits.shape
            u0, v0 = max(0, -x0), max(0, -y0)
            u1, v1 = min(w, width - x0), min(h, height - y0)
            if u1 > u0 and v1 > v0:
                values = raytrace.occupancy_values(self.hits[u0:u1, v0:v1],
                                                   self.visits[u0:u1, v0:v1],
                                                   self.builder.params.occ_thresh)
                data[y0 + v0:y0 + v1, x0 + u0:x0 + u1] = values.T
                known = (x0 + u0, y0 + v0, x0 + u1, y0 + v1)
        return OccupancyGrid(data, self.builder.params.delta, geometry.cell_to_world(0, 0),
                             known)
