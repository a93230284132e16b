"""Laser scans ↔ ``sensor_msgs/LaserScan`` (stageros conventions, ros_interfaces.md §1.5).

stageros fills angle_min/max = ∓fov/2, angle_increment = fov/(samples−1), range_min/max from
the sensor, time_increment = scan_time = 0, and intensities = the hit model's ranger_return
(1 for a wall, 0 when nothing is hit within range_max).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from sensor_msgs.msg import LaserScan

from slam_predict.ros.conversions.geometry import time_from_ros, time_to_ros
from slam_predict.world.model import LaserSpec


@dataclass
class ScanData:
    """One planar scan on our side.

    Attributes:
        ranges: float32 ranges, m.
        angle_min: bearing of the first beam, rad (laser frame).
        angle_increment: rad between beams.
        range_min, range_max: sensor limits, m.
        stamp: s of sim time.
        frame_id: TF frame of the laser.
        intensities: float32 per beam (may be empty).
        scan_time, time_increment: s (0 for a simulated instantaneous scan, as stageros).
    """

    ranges: np.ndarray
    angle_min: float
    angle_increment: float
    range_min: float
    range_max: float
    stamp: float = 0.0
    frame_id: str = "base_laser_link"
    intensities: np.ndarray = field(default_factory=lambda: np.zeros(0, np.float32))
    scan_time: float = 0.0
    time_increment: float = 0.0

    def __post_init__(self) -> None:
        self.ranges = np.asarray(self.ranges, dtype=np.float32)
        self.intensities = np.asarray(self.intensities, dtype=np.float32)

    @property
    def angle_max(self) -> float:
        """Bearing of the last beam, rad."""
        return self.angle_min + self.angle_increment * max(len(self.ranges) - 1, 0)

    def angles(self) -> np.ndarray:
        """Bearings of all beams, rad."""
        return self.angle_min + self.angle_increment * np.arange(len(self.ranges))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, ScanData):
            return NotImplemented
        return (np.array_equal(self.ranges, other.ranges)
                and np.array_equal(self.intensities, other.intensities)
                and (self.angle_min, self.angle_increment, self.range_min, self.range_max,
                     self.stamp, self.frame_id, self.scan_time, self.time_increment)
                == (other.angle_min, other.angle_increment, other.range_min, other.range_max,
                    other.stamp, other.frame_id, other.scan_time, other.time_increment))


def scan_data(ranges: np.ndarray, laser: LaserSpec, stamp: float,
              frame_id: str = "base_laser_link", with_intensities: bool = True) -> ScanData:
    """A :class:`ScanData` for ranges of a laser described by ``laser`` (Stage's layout)."""
    ranges = np.asarray(ranges, dtype=np.float32)
    increment = laser.fov / (laser.samples - 1) if laser.samples > 1 else 0.0
    intensities = (np.where(ranges < laser.range_max, 1.0, 0.0).astype(np.float32)
                   if with_intensities else np.zeros(0, np.float32))
    return ScanData(ranges, -laser.fov / 2.0, increment, laser.range_min, laser.range_max,
                    stamp, frame_id, intensities)


def scan_to_ros(scan: ScanData) -> LaserScan:
    """:class:`ScanData` → sensor_msgs/LaserScan."""
    msg = LaserScan()
    msg.header.stamp = time_to_ros(scan.stamp)
    msg.header.frame_id = scan.frame_id
    msg.angle_min = float(scan.angle_min)
    msg.angle_max = float(scan.angle_max)
    msg.angle_increment = float(scan.angle_increment)
    msg.time_increment = float(scan.time_increment)
    msg.scan_time = float(scan.scan_time)
    msg.range_min = float(scan.range_min)
    msg.range_max = float(scan.range_max)
    msg.ranges = scan.ranges.tolist()
    msg.intensities = scan.intensities.tolist()
    return msg


def scan_from_ros(msg: LaserScan, stamp: float | None = None) -> ScanData:
    """sensor_msgs/LaserScan → :class:`ScanData` (``stamp`` overrides the header's)."""
    return ScanData(np.asarray(msg.ranges, dtype=np.float32), float(msg.angle_min),
                    float(msg.angle_increment), float(msg.range_min), float(msg.range_max),
                    time_from_ros(msg.header.stamp) if stamp is None else stamp,
                    msg.header.frame_id, np.asarray(msg.intensities, dtype=np.float32),
                    float(msg.scan_time), float(msg.time_increment))
