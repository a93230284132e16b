"""The laser-swept floor (explore.seen) against a slow reference: each cell's square clipped
against each beam's segment (slab method), the segment ending where the beam first enters an
occupied cell, leaves the bitmap or reaches its range."""
from __future__ import annotations

import numpy as np
import pytest
from explore_worlds import rooms_world

from slam_predict.explore.coverage import reachable_free
from slam_predict.explore.seen import poses_at, seen_mask, seen_share
from slam_predict.sim.raycast import GridFrame


def cell_intervals(world, origin, direction):
    """Ray parameters (m) where the ray origin + t·direction enters and leaves every cell."""
    frame = GridFrame.of_world(world)
    rows, cols = world.occupied.shape
    res = frame.resolution
    col_edges = frame.x_left + np.arange(cols + 1) * res
    row_edges = frame.y_top - np.arange(rows + 1) * res
    with np.errstate(divide="ignore", invalid="ignore"):
        tx = (col_edges - origin[0]) / direction[0]
        ty = (row_edges - origin[1]) / direction[1]
    x_in, x_out = np.minimum(tx[:-1], tx[1:]), np.maximum(tx[:-1], tx[1:])
    y_in, y_out = np.minimum(ty[:-1], ty[1:]), np.maximum(ty[:-1], ty[1:])
    t_in = np.maximum(y_in[:, None], x_in[None, :])
    t_out = np.minimum(y_out[:, None], x_out[None, :])
    return t_in, t_out


def reference_seen(world, laser_poses, angles, reach_m):
    seen = np.zeros(world.occupied.shape, bool)
    for x, y, yaw in laser_poses:
        for a in angles:
            direction = np.array([np.cos(yaw + a), np.sin(yaw + a)])
            t_in, t_out = cell_intervals(world, (x, y), direction)
            crossed = (t_out > t_in) & (t_out > 0)
            hits = crossed & world.occupied
            end = min(reach_m, t_in[hits].min() if hits.any() else np.inf,
                      t_out[crossed].max())
            seen |= crossed & ~world.occupied & (t_in < end)
    return seen


def test_seen_mask_matches_the_slow_reference():
    world = rooms_world(rooms_x=3, rooms_y=2, room_m=3.0, res=0.1)
    rng = np.random.default_rng(7)
    reach = reachable_free(world, 0.2)
    rows, cols = np.nonzero(reach)
    picks = rng.choice(len(rows), 12, replace=False)
    centres = world.cell_to_world(np.stack([rows[picks], cols[picks]], axis=1))
    jitter = rng.uniform(-0.04, 0.04, centres.shape)
    poses = np.column_stack([centres + jitter, rng.uniform(-np.pi, np.pi, len(picks))])
    angles = np.linspace(-2.0, 2.0, 23) + 1e-3
    for reach_m in (1.5, 30.0):
        ours = seen_mask(world, poses, (0.0, 0.0, 0.0), angles, reach_m)
        assert np.array_equal(ours, reference_seen(world, poses, angles, reach_m))


def test_laser_offset_and_share():
    world = rooms_world(rooms_x=2, rooms_y=1, room_m=3.0, res=0.1)
    reach = reachable_free(world, 0.2)
    start = world.start_pose
    laser = (0.3, 0.0, np.pi / 2)
    ours = seen_mask(world, start[None, :], laser, np.array([0.01]), 30.0)
    from slam_predict.geometry import compose

    expected = reference_seen(world, compose(start, np.array(laser))[None, :], [0.01], 30.0)
    assert np.array_equal(ours, expected) and ours.any()
    assert seen_share(reach, ours) == pytest.approx((reach & ours).sum() / reach.sum())
    assert seen_share(reach, np.ones_like(reach)) == 1.0
    assert seen_share(np.zeros_like(reach), ours) == 0.0


def test_poses_at_takes_the_latest_pose_at_or_before():
    times = np.array([0.1, 0.2, 0.3])
    track = np.arange(9.0).reshape(3, 3)
    got = poses_at(np.array([0.1, 0.25, 0.3, 5.0, 0.0]), times, track)
    assert np.array_equal(got, track[[0, 1, 2, 2, 0]])


def test_sweep_poses_keeps_a_pose_per_quarter_metre_or_quarter_radian():
    from slam_predict.explore.seen import sweep_poses

    creep = np.column_stack([np.arange(0, 1.0, 0.01), np.zeros(100), np.zeros(100)])
    kept = sweep_poses(creep)
    assert np.allclose(kept[:, 0], [0.0, 0.25, 0.5, 0.75])
    turn = np.column_stack([np.zeros(50), np.zeros(50), np.linspace(0, 1.0, 50)])
    assert len(sweep_poses(turn)) == 4
    assert len(sweep_poses(np.empty((0, 3)))) == 0


def test_usable_range_caps_the_laser_by_the_slam_back_end():
    from types import SimpleNamespace

    from slam_predict.explore.seen import usable_range

    assert usable_range(SimpleNamespace(maxUrange=30.0), 80.0) == 30.0
    assert usable_range(SimpleNamespace(max_laser_range=20.0), 10.0) == 10.0
    assert usable_range(SimpleNamespace(), 80.0) == 80.0
    assert usable_range(SimpleNamespace(maxUrange=None), 80.0) == 80.0


def test_swept_coverage_of_a_tour_of_the_rooms_is_complete():
    """A robot that stands on every metre of the floor sweeps all of it; one that stays at its
    start in the corridor does not."""
    from slam_predict.explore.seen import swept_coverage
    from slam_predict.sensor import LaserConfig

    world = rooms_world(rooms_x=3, rooms_y=2, room_m=3.0, res=0.1)
    reach = reachable_free(world, 0.2)
    laser = LaserConfig(fov=2 * np.pi * 359 / 360, samples=720, range_max=30.0)
    rows, cols = np.nonzero(reach)
    lattice = (rows % 10 == 5) & (cols % 10 == 5)             # a pose every metre
    spots = world.cell_to_world(np.stack([rows[lattice], cols[lattice]], axis=1))
    tour = np.column_stack([spots, np.zeros(len(spots))])
    assert swept_coverage(world, reach, tour, laser, 30.0) > 0.97
    corridor = world.start_pose[None, :]
    assert swept_coverage(world, reach, corridor, laser, 30.0) < 0.6
