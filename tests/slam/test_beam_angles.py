"""The scan matcher's beam angles as slam_gmapping gives them to openslam_gmapping.

The node builds ``RangeSensor("FLASER", N, |angle_increment|, ...)``, whose constructor sets beam
i to −0.5·inc·N + i·inc (rangesensor.cpp), in the frame turned to the scan's centre
((angle_min + angle_max)/2); its published map uses the symmetric angles
−|angle_max − angle_min|/2 + i·inc instead (slam_gmapping.cpp, laser_angles_).
"""
import math

import numpy as np
import pytest

from slam_predict.geometry import compose
from slam_predict.slam import LaserGeometry
from slam_predict.slam.gmapping.filter import GMapping, centred_laser, range_sensor_angles
from slam_predict.slam.gmapping.params import GMappingParams


def test_carmen_flaser_angles_by_hand():
    """180 beams, 1°, from −90°: the centre is −0.5°; the node's filter beams run from −90° to
    +89° about it, i.e. from −90.5° to +88.5° in the laser frame (half a beam clockwise)."""
    deg = math.pi / 180
    laser = LaserGeometry(np.radians(np.arange(-90.0, 90.0)), (0.1, 0.0, 0.0), 50.0)
    pose, symmetric = centred_laser(laser)
    np.testing.assert_allclose(pose, [0.1, 0.0, -0.5 * deg])
    np.testing.assert_allclose(symmetric[[0, 1, -1]], np.array([-89.5, -88.5, 89.5]) * deg)
    node = range_sensor_angles(symmetric)
    np.testing.assert_allclose(node[[0, 1, 90, -1]], np.array([-90.0, -89.0, 0.0, 89.0]) * deg,
                               atol=1e-12)
    np.testing.assert_allclose(node + pose[2], laser.angles - 0.5 * deg, atol=1e-12)


def _constructor_loop(n, res):
    """rangesensor.cpp's loop, literally: angle = −.5·res·n; angle += res per beam."""
    out, angle = [], -0.5 * res * n
    for _ in range(n):
        out.append(angle)
        angle += res
    return np.array(out)


@pytest.mark.parametrize("n, res", [(181, math.radians(1.0)), (360, math.radians(0.5)),
                                    (541, math.radians(0.5)), (2, 0.3)])
def test_equals_the_range_sensor_constructor(n, res):
    symmetric = (np.arange(n) - 0.5 * (n - 1)) * res
    np.testing.assert_allclose(range_sensor_angles(symmetric), _constructor_loop(n, res),
                               atol=1e-12)


@pytest.mark.parametrize("flag", [True, False])
def test_gmapping_matches_with_node_angles_and_maps_with_symmetric(flag):
    laser = LaserGeometry(np.radians(np.arange(-90.0, 90.0)), (0.0, 0.0, 0.0), 50.0)
    slam = GMapping(GMappingParams(particles=2, range_sensor_angles=flag), laser,
                    np.random.default_rng(0))
    _, symmetric = centred_laser(laser)
    expected = range_sensor_angles(symmetric) if flag else symmetric
    np.testing.assert_array_equal(slam.filter.angles, expected)
    np.testing.assert_array_equal(slam.builder.ca, np.cos(symmetric))
    # reported robot poses undo the centred frame whatever the matcher's angles
    turned_back = compose(slam.laser_pose([1.0, 2.0, 0.3]), [0.0, 0.0, math.radians(0.5)])
    np.testing.assert_allclose(turned_back, [1.0, 2.0, 0.3])
