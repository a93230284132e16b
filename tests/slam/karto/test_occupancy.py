"""Karto's grid build against a per-beam pure-Python loop."""
import math

import numpy as np

from slam_predict.slam import LaserGeometry
from slam_predict.slam.karto.backend import range_finder
from slam_predict.slam.karto.occupancy import cell_states, counts_from_scans
from slam_predict.slam.karto.scan import LocalizedScan


def bresenham(x0, y0, x1, y1):
    """The cells of Karto's TraceLine, written the obvious way."""
    steep = abs(y1 - y0) > abs(x1 - x0)
    if steep:
        x0, y0, x1, y1 = y0, x0, y1, x1
    if x0 > x1:
        x0, x1, y0, y1 = x1, x0, y1, y0
    cells, error, y = [], 0, y0
    for x in range(x0, x1 + 1):
        cells.append((y, x) if steep else (x, y))
        error += abs(y1 - y0)
        if 2 * error >= x1 - x0:
            y += 1 if y0 < y1 else -1
            error -= x1 - x0
    return cells


def reference_counts(scans, resolution, shape, offset):
    passes, hits = np.zeros(shape, int), np.zeros(shape, int)
    rnd = lambda v: math.floor(v + 0.5)  # noqa: E731
    for scan in scans:
        sx, sy, _ = scan.sensor_pose
        laser = scan.laser
        for k, r in enumerate(scan.ranges):
            if r <= laser.minimum_range or r >= laser.maximum_range:
                continue
            px, py = scan.points[k]
            if r >= laser.range_threshold:
                px = sx + laser.range_threshold / r * (px - sx)
                py = sy + laser.range_threshold / r * (py - sy)
            gx, gy = rnd((px - offset[0]) / resolution), rnd((py - offset[1]) / resolution)
            cells = bresenham(rnd((sx - offset[0]) / resolution),
                              rnd((sy - offset[1]) / resolution), gx, gy)
            for cx, cy in cells:
                if 0 <= cx < shape[1] and 0 <= cy < shape[0]:
                    passes[cy, cx] += 1
            if r < laser.range_threshold - 1e-6 and 0 <= gx < shape[1] and 0 <= gy < shape[0]:
                passes[gy, gx] += 1
                hits[gy, gx] += 1
    return passes, hits


def test_counts_and_states_match_a_per_beam_loop():
    rng = np.random.default_rng(2)
    angles = np.linspace(-2.0, 2.0, 60)
    laser = range_finder(LaserGeometry(angles, (0.1, 0.0, 0.0), 6.0), 4.0)
    scans = [LocalizedScan(laser, k, 0.0, pose, rng.uniform(0.5, 7.0, 60))
             for k, pose in enumerate([(0, 0, 0), (0.7, 0.2, 0.4), (1.1, -0.5, 2.0)])]
    passes, hits, offset = counts_from_scans(scans, 0.1)
    ref_passes, ref_hits = reference_counts(scans, 0.1, passes.shape, offset)
    assert np.array_equal(passes, ref_passes) and np.array_equal(hits, ref_hits)
    states = cell_states(passes, hits, 2, 0.1)
    ratio = np.where(passes > 0, hits / np.maximum(passes, 1), 0)
    expected = np.where(passes > 2, np.where(ratio > 0.1, 100, 0), -1)
    assert np.array_equal(states, expected) and (states == 100).sum() > 10
