"""The ``perfect`` map source: an occupancy grid built from the simulated scans at the TRUE
poses, so the map grows only as the robot sees, with no localisation error.

It has the SLAM back-end interface (:class:`slam_predict.slam.SlamBackend`:
``update(odom_pose, ranges, t) -> pose``, ``map()``, ``pose()``, ``map_to_odom()``) so the
closed loop swaps it for GMapping without other changes. The map is counted with GMapping's own
kernel (:func:`slam_predict.slam.gmapping.raytrace.count_beams`: GridLineTraversal's cells):
along each beam every cell but the end gets a visit, the end cell a visit and a hit (beams
longer than ``maxUrange`` are cut there and mark nothing at their end, beams beyond
``maxRange`` or non-positive are dropped); a cell is unknown (−1) until visited, occupied (100)
when hits/visits > occ_thresh, else free (0). The map frame is the world frame; the grid covers
the world's bitmap plus ``margin`` at ``delta`` m/cell.

Like GMapping, the source can process only some scans (``linearUpdate`` m / ``angularUpdate`` rad
of odometry motion, or ``temporalUpdate`` s, since the last processed scan; the first scan is
always processed; all 0, the default: every scan): a room glimpsed through a door between two
processed scans stays unknown, as in GMapping's map.
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from slam_predict.config import FRACTION, NON_NEGATIVE, POSITIVE, Range
from slam_predict.geometry import compose, inverse
from slam_predict.slam import LaserGeometry, OccupancyGrid, SlamBackend
from slam_predict.slam.gmapping.raytrace import count_beams
from slam_predict.world.model import World


@dataclass
class PerfectMapConfig:
    """Parameters (GMapping's names where they exist): m, m, m, ratio, m, s."""

    delta: float = 0.05
    maxUrange: float = 30.0
    maxRange: float | None = None
    occ_thresh: float = 0.25
    margin: float = 1.0
    map_update_interval: float = 5.0
    linearUpdate: float = 0.0
    angularUpdate: float = 0.0
    temporalUpdate: float = 0.0
    RANGES: ClassVar[dict[str, Range]] = {
        "delta": POSITIVE, "maxUrange": POSITIVE, "maxRange": POSITIVE, "occ_thresh": FRACTION,
        "margin": NON_NEGATIVE, "map_update_interval": NON_NEGATIVE,
        "linearUpdate": NON_NEGATIVE, "angularUpdate": NON_NEGATIVE,
        "temporalUpdate": NON_NEGATIVE}

    def __post_init__(self) -> None:
        if not (self.delta > 0 and self.maxUrange > 0 and 0 < self.occ_thresh < 1):
            raise ValueError("delta and maxUrange must be > 0 and occ_thresh in (0, 1)")
        if self.maxRange is not None and not self.maxRange > 0:
            raise ValueError("maxRange must be > 0")
        if min(self.linearUpdate, self.angularUpdate, self.temporalUpdate) < 0:
            raise ValueError("linearUpdate, angularUpdate and temporalUpdate must be >= 0")


class PerfectMap(SlamBackend):
    """Ground-truth-pose mapping of the simulated scans.

    Args:
        world: gives the extent of the grid.
        laser: beam angles, laser pose on the robot and the sensor's range_max.
        truth: returns the robot's true world pose when the scan being fed was taken.
        config: see :class:`PerfectMapConfig`.
    """

    name = "perfect"

    def __init__(self, world: World, laser: LaserGeometry, truth: Callable[[], np.ndarray],
                 config: PerfectMapConfig | None = None):
        self.config = config or PerfectMapConfig()
        self.laser = laser
        self.truth = truth
        cfg = self.config
        xmin, ymin, _, _ = world.extent
        width, height = world.size_m
        x_left, y_bottom = xmin - cfg.margin, ymin - cfg.margin
        nx = int(math.ceil((width + 2 * cfg.margin) / cfg.delta))
        ny = int(math.ceil((height + 2 * cfg.margin) / cfg.delta))
        self.origin = (x_left, y_bottom)
        self.hits = np.zeros((ny, nx), np.int32)
        self.visits = np.zeros((ny, nx), np.int32)
        sensor_max = laser.range_max if np.isfinite(laser.range_max) else math.inf
        self.max_range = cfg.maxRange if cfg.maxRange is not None else sensor_max
        self.max_urange = min(cfg.maxUrange, self.max_range)
        self._cos = np.cos(laser.angles)
        self._sin = np.sin(laser.angles)
        self._pose = np.zeros(3)
        self._map_to_odom = np.zeros(3)
        self._grid: OccupancyGrid | None = None
        self.scans = 0
        self._last: tuple | None = None   # (last odom pose, t processed, m, rad since)

    def _due(self, odom_pose: np.ndarray, t: float) -> bool:
        """GMapping's rule: is this scan processed? Motion accumulates from scan to scan (path
        length m, absolute turn rad) since the last processed scan."""
        cfg = self.config
        if self._last is not None:
            prev, t_last, dist, turn = self._last
            dist += math.hypot(odom_pose[0] - prev[0], odom_pose[1] - prev[1])
            turn += abs(math.remainder(odom_pose[2] - prev[2], 2 * math.pi))
            self._last = (odom_pose.copy(), t_last, dist, turn)
            if cfg.linearUpdate or cfg.angularUpdate or cfg.temporalUpdate:
                if not (dist >= cfg.linearUpdate or turn >= cfg.angularUpdate
                        or (cfg.temporalUpdate > 0 and t - t_last > cfg.temporalUpdate)):
                    return False
        self._last = (odom_pose.copy(), t, 0.0, 0.0)
        return True

    def update(self, odom_pose, scan_ranges, t: float) -> np.ndarray | None:
        """Integrate one scan taken at the true pose ``truth()``; returns that pose, or None
        when the scan is skipped (GMapping's update rule)."""
        if not self._due(np.asarray(odom_pose, dtype=float), t):
            return None
        true_pose = np.asarray(self.truth(), dtype=float)
        laser = compose(true_pose, np.asarray(self.laser.pose_in_base, dtype=float))
        ranges = np.asarray(scan_ranges, dtype=float)
        keep = np.isfinite(ranges) & (ranges > 0) & (ranges <= self.max_range)
        r = np.minimum(ranges[keep], self.max_urange)
        hit = ranges[keep] <= self.max_urange
        c, s = math.cos(laser[2]), math.sin(laser[2])
        bx = c * self._cos[keep] - s * self._sin[keep]
        by = s * self._cos[keep] + c * self._sin[keep]
        ox, oy = self.origin
        d = self.config.delta
        ends_x = np.floor((laser[0] + r * bx - ox) / d).astype(np.int64)
        ends_y = np.floor((laser[1] + r * by - oy) / d).astype(np.int64)
        x0 = int(math.floor((laser[0] - ox) / d))
        y0 = int(math.floor((laser[1] - oy) / d))
        count_beams(self.hits.T, self.visits.T, x0, y0, ends_x, ends_y, hit)  # [x, y] views
        self._pose = true_pose
        self._map_to_odom = compose(true_pose, inverse(np.asarray(odom_pose, dtype=float)))
        self._grid = None
        self.scans += 1
        return true_pose.copy()

    def map(self) -> OccupancyGrid:
        """The current grid (int8 −1/0/100, row 0 = lowest y)."""
        if self._grid is None:
            data = np.full(self.hits.shape, -1, np.int8)
            seen = self.visits > 0
            occupied = self.hits > self.config.occ_thresh * self.visits
            data[seen] = 0
            data[seen & occupied] = 100
            self._grid = OccupancyGrid(data, self.config.delta, self.origin)
        return self._grid

    def pose(self) -> np.ndarray:
        return self._pose.copy()

    def map_to_odom(self) -> np.ndarray:
        return self._map_to_odom.copy()
