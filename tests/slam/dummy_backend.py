"""A test-only SLAM back-end, ``dummy``: it trusts the odometry (map frame = odom frame) and
counts beam hits and passes per cell.

It is registered the way a user's back-end is: by importing this module, either from a test or
through ``SLAM_PREDICT_EXTRA_BACKENDS=<this file>`` (the rostest's launch sets it). It uses
nothing of slam_predict but the public interface of :mod:`slam_predict.slam`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from slam_predict import slam
from slam_predict.config import POSITIVE, Range, from_dict
from slam_predict.errors import InputError
from slam_predict.geometry import compose

NAME = "dummy"


@dataclass
class DummyParams:
    """Map extent and resolution (m), update triggers (m, rad, s), range cap (m)."""

    xmin: float = -30.0
    ymin: float = -30.0
    xmax: float = 30.0
    ymax: float = 30.0
    delta: float = 0.1
    map_update_interval: float = 2.0
    linear_update: float = 0.3
    angular_update: float = 0.3
    temporal_update: float = 5.0
    max_range: float = 8.0
    RANGES: ClassVar[dict[str, Range]] = {"delta": POSITIVE, "map_update_interval": POSITIVE,
                                          "max_range": POSITIVE}


class DummyMapper(slam.SlamBackend):
    """Dead-reckoning mapper: a processed scan (the first, then after ``linear_update`` m or
    ``angular_update`` rad of odometry or ``temporal_update`` s) marks the cells its beams pass
    as seen free and its end points as hit; a cell is occupied when over a quarter of its visits
    were hits."""

    name = NAME
    label = "Dummy odometry mapper"

    @classmethod
    def params_from_dict(cls, data, source: str = "<config>") -> DummyParams:
        data = dict(data or {})
        kind = data.pop("type", NAME)
        if kind != NAME:
            raise InputError(f"SLAM type '{kind}' is not {NAME}", source)
        return from_dict(DummyParams, data, source)

    @classmethod
    def extent_of(cls, params: DummyParams):
        return (params.xmin, params.ymin, params.xmax, params.ymax)

    def __init__(self, params: DummyParams, laser: slam.LaserGeometry, rng=None):
        self.params = params
        self.laser = laser
        width = int(round((params.xmax - params.xmin) / params.delta))
        height = int(round((params.ymax - params.ymin) / params.delta))
        self.hits = np.zeros((height, width), np.int32)
        self.visits = np.zeros((height, width), np.int32)
        self._odom = np.zeros(3)
        self._last = None
        self._last_t = -math.inf
        self._count = 0
        self._processed = []   # (scan number, t, pose)

    @property
    def beam_angles(self) -> np.ndarray:
        return self.laser.angles

    def update(self, odom_pose, scan_ranges, t: float):
        self._odom = np.asarray(odom_pose, float)
        number, self._count = self._count, self._count + 1
        if not self._due(float(t)):
            return None
        self._last, self._last_t = self._odom.copy(), float(t)
        self._integrate(np.asarray(scan_ranges, float))
        self._processed.append((number, float(t), self._odom.copy()))
        return self.pose()

    def _due(self, t: float) -> bool:
        if self._last is None or t - self._last_t > self.params.temporal_update:
            return True
        moved = math.hypot(*(self._odom[:2] - self._last[:2]))
        turned = abs(math.remainder(self._odom[2] - self._last[2], 2 * math.pi))
        return moved >= self.params.linear_update or turned >= self.params.angular_update

    def _integrate(self, ranges: np.ndarray) -> None:
        p = self.params
        sensor = compose(self._odom, np.asarray(self.laser.pose_in_base, float))
        bearing = sensor[2] + self.laser.angles
        hit = np.isfinite(ranges) & (ranges < min(p.max_range, self.laser.range_max - 1e-6))
        reach = np.where(np.isfinite(ranges), np.minimum(ranges, p.max_range), p.max_range)
        steps = np.arange(0.0, p.max_range, 0.5 * p.delta)
        along = steps[None, :] < reach[:, None]
        xs = sensor[0] + steps[None, :] * np.cos(bearing)[:, None]
        ys = sensor[1] + steps[None, :] * np.sin(bearing)[:, None]
        self._mark(self.visits, xs[along], ys[along])
        ends_x = sensor[0] + reach[hit] * np.cos(bearing[hit])
        ends_y = sensor[1] + reach[hit] * np.sin(bearing[hit])
        self._mark(self.visits, ends_x, ends_y)
        self._mark(self.hits, ends_x, ends_y)

    def _mark(self, counts: np.ndarray, xs: np.ndarray, ys: np.ndarray) -> None:
        p = self.params
        cols = np.floor((xs - p.xmin) / p.delta).astype(np.int64)
        rows = np.floor((ys - p.ymin) / p.delta).astype(np.int64)
        inside = (cols >= 0) & (cols < counts.shape[1]) & (rows >= 0) & (rows < counts.shape[0])
        cells = np.unique(rows[inside] * counts.shape[1] + cols[inside])
        counts.reshape(-1)[cells] += 1

    def map(self) -> slam.OccupancyGrid:
        data = np.full(self.hits.shape, -1, np.int8)
        seen = self.visits > 0
        data[seen] = 0
        data[seen & (self.hits * 4 > self.visits)] = 100
        return slam.OccupancyGrid(data, self.params.delta, (self.params.xmin, self.params.ymin))

    def pose(self) -> np.ndarray:
        return self._odom.copy()

    def map_to_odom(self) -> np.ndarray:
        return np.zeros(3)

    def trajectory(self):
        if not self._processed:
            return np.zeros(0, np.int64), np.zeros(0), np.zeros((0, 3))
        numbers, times, poses = zip(*self._processed, strict=True)
        return np.arange(len(numbers)), np.array(times), np.array(poses)

    def stats(self) -> dict:
        return {"scans_seen": self._count, "scans_processed": len(self._processed)}


if NAME not in slam.available():
    slam.register(NAME, DummyMapper)
