"""SLAM input: scans with the robot's odometry, read from a CARMEN log (this module) or a ROS bag
(:mod:`slam_predict.slam.bag_input`); :func:`slam_predict.slam.runner.read_input` picks one.

CARMEN logs: ODOM / FLASER / ROBOTLASER1 lines (plain or .gz). The robot's raw odometry is
taken from each scan's odom fields (FLASER ``odom_*``, ROBOTLASER1 ``robot_*``); the scan's own
pose fields (FLASER ``x y theta``) are kept apart as the reference trajectory. The laser sits
``PARAM robot_frontlaser_offset`` m ahead of the robot centre. When the sensor's range_max is
unknown, it is the largest reading of the log (CARMEN's no-return value).
"""
from __future__ import annotations

import dataclasses
import math
import os
from dataclasses import dataclass, field

import numpy as np

from slam_predict.errors import InputError, require_file
from slam_predict.slam import LaserGeometry


@dataclass
class SlamInput:
    """Scans with the robot's odometry: times (N,) s, odometry (N, 3), ranges (N, B) m, the laser,
    and the reference poses (N, 3) when the input has them."""

    path: str
    times: np.ndarray
    odometry: np.ndarray
    ranges: np.ndarray
    laser: LaserGeometry
    reference: np.ndarray | None = None
    info: dict = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.times)

    def take(self, indices) -> SlamInput:
        """The scans at ``indices`` (in that order), e.g. those a compute delay let through."""
        index = np.asarray(indices, dtype=np.int64)
        reference = self.reference[index] if self.reference is not None else None
        return dataclasses.replace(self, times=self.times[index], odometry=self.odometry[index],
                                   ranges=self.ranges[index], reference=reference)


def read_carmen_input(path: os.PathLike | str, max_scans: int | None = None) -> SlamInput:
    """A CARMEN log as :class:`SlamInput` (first ``max_scans`` scans only, when given)."""
    from slam_predict.formats.carmen import read_log

    path = os.fspath(path)
    log = read_log(require_file(path, "SLAM input"))
    scans = log.scans[:max_scans] if max_scans is not None else log.scans
    if not scans:
        raise InputError("no FLASER or ROBOTLASER1 scan in the log", path)
    beams = len(scans[0].ranges)
    if any(len(s.ranges) != beams for s in scans):
        raise InputError("scans have different numbers of beams", path)
    ranges = np.array([s.ranges for s in scans], dtype=np.float64)
    offset = log.param_float("robot_frontlaser_offset", 0.0)
    side_offset = log.param_float("robot_frontlaser_side_offset", 0.0)
    sensor_max = scans[0].max_range
    if not math.isfinite(sensor_max):
        sensor_max = float(np.max(ranges))
    laser = LaserGeometry(scans[0].angles, (offset, side_offset, 0.0), sensor_max)
    return SlamInput(path=path, times=np.array([s.timestamp for s in scans]),
                     odometry=np.array([s.odom_pose for s in scans]), ranges=ranges, laser=laser,
                     reference=np.array([s.pose for s in scans]),
                     info={"format": "carmen", "scan_type": scans[0].kind, "beams": beams,
                           "laser_offset_m": offset, "scans_in_log": len(log.scans)})
