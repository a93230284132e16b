"""The incrementally updated published map equals the full updateMap rebuild, cell for cell."""
import dataclasses

import numpy as np
import pytest
from slam_scan import ANGLES, scan_of

from slam_predict.slam import LaserGeometry
from slam_predict.slam.gmapping import kernels
from slam_predict.slam.gmapping.filter import GMapping
from slam_predict.slam.gmapping.gridmap import IncrementalMap, MapBuilder, grow_geometry
from slam_predict.slam.gmapping.maps import Geometry
from slam_predict.slam.gmapping.params import GMappingParams, load_params, with_ranges
from slam_predict.slam.runner import read_input


def same_grid(a, b):
    """``a`` (the incremental map) equals ``b`` cell for cell, and every cell outside the box
    it calls ``known`` is unknown."""
    assert a.data.shape == b.data.shape
    if a.known is not None:
        x0, y0, x1, y1 = a.known
        outside = np.ones(a.data.shape, bool)
        outside[max(0, y0):y1, max(0, x0):x1] = False
        assert np.all(a.data[outside] == -1)
    assert a.origin == b.origin and a.resolution == b.resolution
    assert np.array_equal(a.data, b.data)


def check_run(slam, odometry, ranges, times, every=1):
    """Feed the scans; compare map() with rebuilt_map() after every ``every``-th processed scan.
    Returns (best-particle switches seen, maps compared)."""
    best, switches, compared, processed = None, 0, 0, 0
    for k in range(len(odometry)):
        if slam.update(odometry[k], ranges[k], times[k]) is None:
            continue
        processed += 1
        index = slam.filter.best_index
        switches += best is not None and index != best
        best = index
        if processed % every == 0:
            same_grid(slam.map(), slam.rebuilt_map())
            compared += 1
    return switches, compared


def test_real_log_slice_with_resampling_and_switches(shared_dir):
    data = read_input(shared_dir / "data" / "slam_inputs" / "intel.log.gz", max_scans=160)
    params = load_params(shared_dir / "baselines" / "gmapping_real_intel.yaml")
    params = dataclasses.replace(params, particles=12)
    slam = GMapping(params, data.laser, np.random.default_rng(4))
    switches, compared = check_run(slam, data.odometry, data.ranges, data.times, every=3)
    stats = slam.published.stats
    assert slam.filter.resamples >= 3 and switches >= 3 and compared >= 40
    assert stats["removed"] > 0, "no particle switch changed the trajectory's past"
    assert stats["added"] < 3 * slam.filter.count  # incremental, not rebuilt every time
    assert stats["restarts"] == 1


def synthetic_run(seed, steps=40, particles=8, **overrides):
    params = dataclasses.replace(GMappingParams(), particles=particles, linearUpdate=0.2,
                                 angularUpdate=0.2, temporalUpdate=-1.0, **overrides)
    laser = LaserGeometry(ANGLES, (0.1, 0.0, 0.0), 30.0)
    slam = GMapping(params, laser, np.random.default_rng(seed))
    rng = np.random.default_rng(seed + 100)
    t = np.arange(steps) * 0.5
    truth = np.stack([-3.5 + 0.17 * np.arange(steps), 0.6 * np.sin(np.arange(steps) / 6.0),
                      0.2 * np.sin(np.arange(steps) / 5.0)], axis=1)
    odometry = truth + np.cumsum(rng.normal(0.0, [0.01, 0.01, 0.004], truth.shape), axis=0)
    laser_poses = truth + np.stack([0.1 * np.cos(truth[:, 2]), 0.1 * np.sin(truth[:, 2]),
                                    np.zeros(steps)], axis=1)
    ranges = np.array([scan_of(p) for p in laser_poses])
    return slam, odometry, ranges, t


@pytest.mark.parametrize("seed", [0, 1])
def test_synthetic_run_matches_rebuild(seed):
    slam, odometry, ranges, t = synthetic_run(seed)
    check_run(slam, odometry, ranges, t)
    assert slam.filter.count > 10


def test_growth_of_the_map_restarts_and_still_matches():
    """A map smaller than the room grows; the cache restarts on the new centre."""
    slam, odometry, ranges, t = synthetic_run(2, steps=30, xmin=-2.0, ymin=-2.0, xmax=2.0,
                                              ymax=2.0)
    check_run(slam, odometry, ranges, t)
    assert slam.published.stats["restarts"] >= 2


def test_grow_geometry_equals_grow_to_row_by_row():
    rng = np.random.default_rng(5)
    centre = rng.uniform(-30.0, 30.0, (60, 2))
    size = rng.uniform(0.0, 25.0, (60, 2))
    bounds = np.concatenate([centre - size, centre + size], axis=1)
    fast = grow_geometry(Geometry.bounded(-10.0, -10.0, 10.0, 10.0, 0.05), bounds)
    slow = Geometry.bounded(-10.0, -10.0, 10.0, 10.0, 0.05)
    for row in bounds:
        slow.grow_to(tuple(row))
    assert fast == slow and fast.nx > 13


def test_scans_bounds_equals_scan_bounds():
    rng = np.random.default_rng(6)
    poses = rng.uniform(-5.0, 5.0, (7, 3))
    readings = rng.uniform(0.0, 40.0, (7, len(ANGLES)))
    readings[:, ::7] = 0.0
    ca, sa = np.cos(ANGLES), np.sin(ANGLES)
    got = kernels.scans_bounds(poses, readings, ca, sa, 35.0, 20.0)
    for k in range(len(poses)):
        assert tuple(got[k]) == kernels.scan_bounds(*poses[k], readings[k], ca, sa, 35.0, 20.0)


def test_switching_between_two_trajectories_uses_subtraction():
    """Counts are removed exactly: alternating two paths that share a prefix."""
    params = with_ranges(GMappingParams(), 30.0)
    builder = MapBuilder(params, ANGLES)
    reference = MapBuilder(params, ANGLES)
    cache = IncrementalMap(builder)
    rng = np.random.default_rng(7)
    shared = np.stack([np.linspace(-3, 0, 6), np.zeros(6), np.zeros(6)], axis=1)
    branch_a = shared[-1] + np.array([[0.3, 0.2, 0.1], [0.6, 0.5, 0.2]])
    branch_b = shared[-1] + np.array([[0.2, -0.3, -0.1], [0.5, -0.6, -0.3], [0.9, -1.0, -0.2]])
    readings = {k: scan_of(p) + rng.normal(0, 0.01, len(ANGLES)) for k, p in
                enumerate(np.concatenate([shared, branch_b]))}
    paths = [np.concatenate([shared, branch_a]), np.concatenate([shared, branch_b]),
             np.concatenate([shared, branch_a]), shared[:3], np.concatenate([shared, branch_b])]
    for poses in paths:
        scans = np.arange(len(poses))
        grid = cache.build(scans, poses, readings.__getitem__)
        newest_first = np.array([readings[k] for k in scans])[::-1]
        same_grid(grid, reference.build(poses[::-1], newest_first))
    assert cache.stats["removed"] > 0
