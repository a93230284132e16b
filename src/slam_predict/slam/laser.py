"""Laser set-up as slam_gmapping does it: planarity test, beam bearings in the base frame,
range clean-up. Pure numpy (shared by the ROS node and the bag reader)."""
from __future__ import annotations

import numpy as np

from slam_predict.slam import LaserGeometry


def quaternion_matrix(x: float, y: float, z: float, w: float) -> np.ndarray:
    """3 x 3 rotation matrix of a unit quaternion."""
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def laser_geometry(rotation: np.ndarray, translation, angle_min: float, angle_increment: float,
                   beams: int, range_max: float) -> tuple[LaserGeometry | None, bool]:
    """(laser in the base frame, whether ranges must be reversed), or (None, False) when the
    laser is not planar (its z axis not within 0.001 of ±base z, slam_gmapping's test).

    ``rotation``/``translation``: the laser frame in the base frame (3 x 3, m). Beam bearings are
    expressed in the base frame, increasing; ranges are to be reversed when the scan runs
    clockwise there (upside-down laser or negative increment).
    """
    rotation = np.asarray(rotation, dtype=float)
    up = float(rotation[2, 2])
    if abs(abs(up) - 1.0) > 0.001:
        return None, False
    if up > 0:
        # upright: base bearing = mounting yaw + laser bearing (same formula as CARMEN's
        # start_angle + i·angular_res, so a log and a bag of one scan give the same angles)
        yaw = float(np.arctan2(rotation[1, 0], rotation[0, 0]))
        angles = (yaw + angle_min) + angle_increment * np.arange(beams)
    else:
        bearings = angle_min + angle_increment * np.arange(beams)
        dirs = rotation @ np.vstack([np.cos(bearings), np.sin(bearings), np.zeros(beams)])
        angles = np.unwrap(np.arctan2(dirs[1], dirs[0]))
    reverse = beams > 1 and angles[-1] < angles[0]
    if reverse:
        angles = angles[::-1]
    return LaserGeometry(angles, (float(translation[0]), float(translation[1]), 0.0),
                         float(range_max)), bool(reverse)


def prepare_ranges(ranges, range_min: float, range_max: float, reverse: bool) -> np.ndarray:
    """float64 ranges for the filter: < range_min (or NaN) → range_max, reversed if asked."""
    r = np.asarray(ranges, dtype=float)
    r = np.where(np.isnan(r) | (r < range_min), float(range_max), r)
    return r[::-1].copy() if reverse else r
