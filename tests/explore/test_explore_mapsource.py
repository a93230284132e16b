"""The perfect map source: ray counting against a slow reference, a map that grows only where
the laser sees, GMapping's range rules, frames."""
from __future__ import annotations

import math

import numpy as np
import pytest

from slam_predict.explore.mapsource import PerfectMap, PerfectMapConfig
from slam_predict.geometry import compose
from slam_predict.nav.kernels import count_rays
from slam_predict.slam import LaserGeometry
from slam_predict.world.model import World


def ref_line(x0, y0, x1, y1):
    """Integer Bresenham line from (x0, y0) to (x1, y1), both ends included."""
    dx, dy = abs(x1 - x0), abs(y1 - y0)
    sx, sy = (1 if x1 >= x0 else -1), (1 if y1 >= y0 else -1)
    err, x, y, out = dx - dy, x0, y0, []
    while True:
        out.append((x, y))
        if (x, y) == (x1, y1):
            return out
        e2 = 2 * err
        if e2 > -dy:
            err -= dy
            x += sx
        if e2 < dx:
            err += dx
            y += sy


@pytest.mark.parametrize("seed", range(3))
def test_count_rays_matches_reference(seed):
    rng = np.random.default_rng(seed)
    hits = np.zeros((30, 40), np.int32)
    visits = np.zeros_like(hits)
    x0, y0 = 20, 15
    ex = rng.integers(-10, 50, 40)
    ey = rng.integers(-10, 40, 40)
    is_hit = rng.random(40) < 0.7
    count_rays(hits, visits, x0, y0, ex, ey, is_hit)
    ref_h = np.zeros_like(hits)
    ref_v = np.zeros_like(hits)
    for x1, y1, h in zip(ex, ey, is_hit):
        cells = ref_line(x0, y0, int(x1), int(y1))
        for x, y in cells:
            if 0 <= x < 40 and 0 <= y < 30:
                ref_v[y, x] += 1
        if h and 0 <= x1 < 40 and 0 <= y1 < 30:
            ref_h[y1, x1] += 1
    np.testing.assert_array_equal(visits, ref_v)
    np.testing.assert_array_equal(hits, ref_h)


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
    for k, (pose, t) in enumerate(zip(poses, times)):
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
    got = [k for k, (pose, t) in enumerate(zip(poses, times))
           if source.update(pose, np.array([1.0, 1.0]), float(t)) is not None]
    want = slow_processed(poses, times, 1.0, 0.25, 5.0)
    assert got == want and 5 < len(got) < 150
    every = PerfectMap(world, laser, lambda: np.array([-3.0, 0.0, 0.0]),
                       PerfectMapConfig(margin=0.5))
    assert all(every.update(p, np.array([1.0, 1.0]), float(t)) is not None
               for p, t in zip(poses, times))
