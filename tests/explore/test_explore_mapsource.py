"""The perfect map source: ray counting against GMapping's line walker, a map that grows only where
the laser sees, GMapping's range rules, frames."""
from __future__ import annotations

import math

import numpy as np
import pytest

from slam_predict.explore.mapsource import PerfectMap, PerfectMapConfig
from slam_predict.geometry import compose
from slam_predict.slam import LaserGeometry
from slam_predict.slam.gmapping.raytrace import count_beams, line_cells
from slam_predict.world.model import World


def counted_with_line_cells(shape, x0, y0, ends_x, ends_y, is_hit):
    """Reference counts [y, x]: every cell of GMapping's line_cells but the end gets a visit,
    the end a hit and a visit when the beam hit (cells outside ``shape`` skipped)."""
    hits, visits = np.zeros(shape, np.int32), np.zeros(shape, np.int32)
    inside = lambda x, y: 0 <= x < shape[1] and 0 <= y < shape[0]  # noqa: E731
    for x1, y1, hit in zip(ends_x, ends_y, is_hit, strict=True):
        cells = [tuple(c) for c in line_cells(x0, y0, int(x1), int(y1))]
        for x, y in cells[:-1]:
            if inside(x, y) and (x, y) != (x1, y1):
                visits[y, x] += 1
        if hit and inside(x1, y1):
            hits[y1, x1] += 1
            visits[y1, x1] += 1
    return hits, visits


@pytest.mark.parametrize("seed", range(5))
def test_beams_are_counted_on_gmappings_line_cells(seed):
    """The perfect map's counting (PerfectMap.update's kernel) against GMapping's own line
    walker on 2000 random beams, many leaving the grid."""
    rng = np.random.default_rng(seed)
    shape = (60, 80)
    x0, y0 = (int(v) for v in rng.integers(-5, 85, 2))
    ends_x = rng.integers(-60, 140, 2000)
    ends_y = rng.integers(-60, 120, 2000)
    is_hit = rng.random(2000) < 0.7
    hits, visits = np.zeros(shape, np.int32), np.zeros(shape, np.int32)
    count_beams(hits.T, visits.T, x0, y0, ends_x, ends_y, is_hit)
    ref_hits, ref_visits = counted_with_line_cells(shape, x0, y0, ends_x, ends_y, is_hit)
    np.testing.assert_array_equal(hits, ref_hits)
    np.testing.assert_array_equal(visits, ref_visits)


def test_perfect_map_counts_a_scan_on_line_cells():
    """PerfectMap.update marks the cells of line_cells from the laser cell to each end cell."""
    world = two_rooms()
    angles = np.linspace(-math.pi, math.pi, 361)[:-1]
    laser = LaserGeometry(angles, (0.0, 0.0, 0.0), 30.0)
    truth = np.array([-2.013, 0.377, 0.0])   # yaw 0: end points computed exactly as update does
    source = PerfectMap(world, laser, lambda: truth, PerfectMapConfig(margin=0.5))
    ranges = cast(world, truth, angles)
    source.update(np.zeros(3), ranges, 0.1)
    ox, oy = source.origin
    ends = truth[:2] + ranges[:, None] * np.stack([np.cos(truth[2] + angles),
                                                   np.sin(truth[2] + angles)], axis=1)
    ends_x = np.floor((ends[:, 0] - ox) / 0.05).astype(int)
    ends_y = np.floor((ends[:, 1] - oy) / 0.05).astype(int)
    x0, y0 = int(math.floor((truth[0] - ox) / 0.05)), int(math.floor((truth[1] - oy) / 0.05))
    ref_hits, ref_visits = counted_with_line_cells(source.hits.shape, x0, y0, ends_x, ends_y,
                                                   np.ones(len(angles), bool))
    np.testing.assert_array_equal(source.hits, ref_hits)
    np.testing.assert_array_equal(source.visits, ref_visits)


def two_rooms() -> World:
    """8 m x 4 m, a wall at x = 0 with no door: the right half can never be seen from the left."""
    occ = np.zeros((80, 160), bool)
    occ[:2, :] = occ[-2:, :] = True
    occ[:, :2] = occ[:, -2:] = True
    occ[:, 79:81] = True
    return World("two_rooms", occ, 0.05, start_pose=np.array([-2.0, 0.0, 0.0]))


def cast(world: World, pose, angles, range_max=30.0, step=0.002, reach=9.0):
    """Ranges by marching every beam in ``step`` m increments (test helper, vectorised)."""
    r = np.arange(0.0, reach, step)
    a = pose[2] + np.asarray(angles)[:, None]
    pts = np.stack([pose[0] + r * np.cos(a), pose[1] + r * np.sin(a)], axis=-1)
    blocked = ~world.is_free_at(pts)
    first = np.argmax(blocked, axis=1)
    return np.where(blocked.any(axis=1), r[first], range_max)


def test_map_grows_only_where_the_laser_sees():
    world = two_rooms()
    angles = np.linspace(-math.pi, math.pi, 181)[:-1]
    laser = LaserGeometry(angles, (0.0, 0.0, 0.0), 30.0)
    truth = np.array([-2.0, 0.0, 0.3])
    source = PerfectMap(world, laser, lambda: truth, PerfectMapConfig(margin=0.5))
    odom = np.array([0.5, -0.2, 0.1])
    pose = source.update(odom, cast(world, truth, angles), 0.1)
    np.testing.assert_allclose(pose, truth)
    np.testing.assert_allclose(compose(source.map_to_odom(), odom), truth, atol=1e-12)
    grid = source.map()
    data = grid.data

    def value(x, y):
        c = int(math.floor((x - grid.origin[0]) / grid.resolution))
        r = int(math.floor((y - grid.origin[1]) / grid.resolution))
        return data[r, c]

    assert value(-1.0, 0.5) == 0            # seen free space
    assert value(2.0, 0.0) == -1            # the other room
    assert value(-0.04, 0.0) == 100         # the dividing wall's face
    assert value(-3.92, 0.0) == 100         # the outer wall's face
    assert (data == 100).sum() > 100 and (data == -1).sum() > data.size / 2


def test_range_rules_follow_gmapping():
    world = two_rooms()
    angles = np.array([0.0, 0.5])
    laser = LaserGeometry(angles, (0.0, 0.0, 0.0), 30.0)
    cfg = PerfectMapConfig(maxUrange=1.0, margin=0.5)
    source = PerfectMap(world, laser, lambda: np.array([-3.0, 0.0, 0.0]), cfg)
    source.update(np.zeros(3), np.array([2.96, 35.0]), 0.1)   # a hit beyond maxUrange, a >maxRange
    grid = source.map()
    res = grid.resolution
    row = int((0.0 - grid.origin[1]) / res)
    seen = np.nonzero(grid.data[row] != -1)[0]
    far = grid.origin[0] + (seen.max() + 1) * res
    assert far == pytest.approx(-2.0, abs=0.06)               # free up to maxUrange only
    assert (grid.data == 100).sum() == 0                      # no hit marked
    beam2 = (grid.data != -1).sum()
    assert beam2 == len(seen)                                 # the 35 m beam was dropped


def slow_processed(poses, times, lin, ang, per):
    """slam_gmapping's scan selection written out: motion summed since the last processed."""
    out, dist, turn, last_t = [], 0.0, 0.0, None
    for k, (pose, t) in enumerate(zip(poses, times, strict=False)):
        if k:
            dist += math.hypot(*(pose[:2] - poses[k - 1][:2]))
            turn += abs(math.remainder(pose[2] - poses[k - 1][2], 2 * math.pi))
        if k == 0 or dist >= lin or turn >= ang or (per > 0 and t - last_t > per):
            out.append(k)
            dist, turn, last_t = 0.0, 0.0, t
    return out


def test_gmapping_update_rule_selects_the_scans_slam_gmapping_processes():
    world = two_rooms()
    angles = np.array([0.0, 1.0])
    laser = LaserGeometry(angles, (0.0, 0.0, 0.0), 30.0)
    rng = np.random.default_rng(0)
    steps = np.cumsum(rng.uniform(0.0, 0.15, size=(200, 3)) * [1, 0.3, 0.4], axis=0)
    poses = steps - [3.0, 0.0, 0.0]
    times = np.cumsum(0.1 + (rng.random(200) < 0.05) * 4.0)    # a few 4 s gaps (temporal)
    cfg = PerfectMapConfig(margin=0.5, linearUpdate=1.0, angularUpdate=0.25,
                           temporalUpdate=5.0)
    source = PerfectMap(world, laser, lambda: np.array([-3.0, 0.0, 0.0]), cfg)
    got = [k for k, (pose, t) in enumerate(zip(poses, times, strict=False))
           if source.update(pose, np.array([1.0, 1.0]), float(t)) is not None]
    want = slow_processed(poses, times, 1.0, 0.25, 5.0)
    assert got == want and 5 < len(got) < 150
    every = PerfectMap(world, laser, lambda: np.array([-3.0, 0.0, 0.0]),
                       PerfectMapConfig(margin=0.5))
    assert all(every.update(p, np.array([1.0, 1.0]), float(t)) is not None
               for p, t in zip(poses, times, strict=False))
