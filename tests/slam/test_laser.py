"""Laser set-up as slam_gmapping does it: planarity, bearings in the base frame, ranges."""
import math

import numpy as np

from slam_predict.slam.laser import laser_geometry, prepare_ranges, quaternion_matrix


def test_laser_geometry_and_ranges():
    laser, reverse = laser_geometry(np.eye(3), (0.2, 0.0, 0.3), -1.0, 0.5, 5, 30.0)
    assert not reverse and np.allclose(laser.angles, [-1.0, -0.5, 0.0, 0.5, 1.0])
    assert laser.pose_in_base == (0.2, 0.0, 0.0) and laser.range_max == 30.0
    flipped = quaternion_matrix(1.0, 0.0, 0.0, 0.0)  # roll pi
    laser, reverse = laser_geometry(flipped, (0, 0, 0), -1.0, 0.5, 5, 30.0)
    assert reverse and np.allclose(laser.angles, [-1.0, -0.5, 0.0, 0.5, 1.0])
    tilted = quaternion_matrix(math.sin(0.05), 0.0, 0.0, math.cos(0.05))
    assert laser_geometry(tilted, (0, 0, 0), -1.0, 0.5, 5, 30.0) == (None, False)
    r = prepare_ranges([0.05, float("nan"), 2.0, float("inf")], 0.1, 30.0, reverse=True)
    assert list(r) == [float("inf"), 2.0, 30.0, 30.0]
