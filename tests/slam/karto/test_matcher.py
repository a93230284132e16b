"""Karto's correlative scan matcher against a brute-force pure-Python correlation search on a
small grid, and on a synthetic scan shifted by a known offset."""
import math

import numpy as np
import pytest

from slam_predict.slam import LaserGeometry
from slam_predict.slam.karto.backend import range_finder, search_settings
from slam_predict.slam.karto.matcher import ScanMatcher, search_steps, smear_kernel
from slam_predict.slam.karto.params import KartoParams
from slam_predict.slam.karto.scan import LocalizedScan

ANGLES = np.linspace(-math.pi / 2, math.pi / 2, 91)


def box_ranges(pose, half=3.0):
    """Ranges of a laser at ``pose`` inside an axis-aligned square room of half side ``half``."""
    x, y, yaw = pose
    out = np.empty(len(ANGLES))
    for k, a in enumerate(ANGLES):
        c, s = math.cos(yaw + a), math.sin(yaw + a)
        hits = [t for t in ((half - x) / c if c > 1e-12 else math.inf,
                            (-half - x) / c if c < -1e-12 else math.inf,
                            (half - y) / s if s > 1e-12 else math.inf,
                            (-half - y) / s if s < -1e-12 else math.inf) if t > 0]
        out[k] = min(hits)
    return out


def setup(search=0.32, resolution=0.02):
    params = KartoParams(max_laser_range=8.0, correlation_search_space_dimension=search,
                         correlation_search_space_resolution=resolution)
    laser = range_finder(LaserGeometry(ANGLES, (0.0, 0.0, 0.0), 10.0), params.max_laser_range)
    matcher = ScanMatcher(search_settings(params), search, resolution, 0.05, 8.0)
    return params, laser, matcher


def brute_force_response(matcher, scan, pose):
    """Mean smeared grid value under the scan's points at ``pose`` (x, y, yaw) — per point in
    Python, on the matcher's own grid."""
    total = 0.0
    res = matcher.resolution
    local = [(r * math.cos(a), r * math.sin(a)) for r, a in zip(
        scan.ranges, scan.laser.minimum_angle + np.arange(len(scan.ranges))
        * scan.laser.angular_resolution, strict=True)]
    cx = math.floor((pose[0] - matcher.offset[0]) / res + 0.5)
    cy = math.floor((pose[1] - matcher.offset[1]) / res + 0.5)
    for lx, ly in local:
        ox = math.cos(pose[2]) * lx - math.sin(pose[2]) * ly
        oy = math.sin(pose[2]) * lx + math.cos(pose[2]) * ly
        gx = cx + matcher.roi[0] + math.floor(ox / res + 0.5)
        gy = cy + matcher.roi[1] + math.floor(oy / res + 0.5)
        index = gx + gy * matcher.width_step
        if 0 <= index < matcher.grid.size:
            total += matcher.grid[index]
    return total / (len(local) * 100.0)


def test_kernel_is_a_rounded_gaussian_of_two_sigma_half_width():
    kernel = smear_kernel(0.1, 0.02)
    assert kernel.shape == (21, 21) and kernel[10, 10] == 100
    assert kernel[10, 15] == round(100 * math.exp(-0.5 * (0.1 / 0.1) ** 2))
    assert np.array_equal(kernel, kernel.T) and np.array_equal(kernel, kernel[::-1])


def test_coarse_search_equals_brute_force_best_pose():
    params, laser, matcher = setup()
    base = LocalizedScan(laser, 0, 0.0, np.zeros(3), box_ranges((0.0, 0.0, 0.0)))
    truth = (0.06, -0.04, 0.05)
    guess = np.array([0.0, 0.0, 0.0])
    scan = LocalizedScan(laser, 1, 0.0, guess, box_ranges(truth))
    scan.set_corrected_pose(guess)
    response, mean, _ = matcher.match(scan, [base], penalize=False, refine=False)
    # brute force over the same candidates on the same grid
    xs = search_steps(0.5 * (matcher.side - 1) * matcher.resolution, 2 * matcher.resolution)
    angles = -params.coarse_search_angle_offset + np.arange(21) * params.coarse_angle_resolution
    best = max(brute_force_response(matcher, scan, (x, y, a))
               for x in xs for y in xs for a in angles)
    assert response == pytest.approx(best, abs=1e-9)
    # the scan was taken at `truth`: the pose found is within an angle step and a few coarse
    # cells of it
    assert abs(mean[2] - truth[2]) <= params.coarse_angle_resolution
    assert np.hypot(*(mean[:2] - truth[:2])) < 0.1


def test_fine_match_recovers_a_known_offset():
    params, laser, matcher = setup(search=0.5, resolution=0.01)
    base = LocalizedScan(laser, 0, 0.0, np.zeros(3), box_ranges((0.0, 0.0, 0.0)))
    truth = np.array([0.12, -0.07, 0.0])
    scan = LocalizedScan(laser, 1, 0.0, np.zeros(3), box_ranges(truth))
    response, mean, cov = matcher.match(scan, [base], penalize=True, refine=True)
    assert response > 0.5
    assert np.allclose(mean[:2], truth[:2], atol=0.02) and abs(mean[2]) < 0.01
    assert np.all(np.linalg.eigvalsh(cov) > 0)


@pytest.mark.parametrize("heading", [0.0, 1.2, -2.5])
def test_angular_variance_is_the_response_weighted_spread_around_the_best_heading(heading):
    """ComputeAngularCovariance is the spread of the fine headings around the best heading
    (not around the heading change): a few fine steps at most, whatever the heading."""
    params, laser, matcher = setup(search=0.5, resolution=0.01)
    base_pose = np.array([0.0, 0.0, heading])
    base = LocalizedScan(laser, 0, 0.0, base_pose, box_ranges(base_pose))
    truth = np.array([0.05, -0.03, heading + 0.01])
    scan = LocalizedScan(laser, 1, 0.0, base_pose, box_ranges(truth))
    response, mean, cov = matcher.match(scan, [base], penalize=True, refine=True)
    assert response > 0.5
    assert 0.0 < cov[2, 2] < (6 * params.fine_search_angle_offset) ** 2
