"""Footprint collision: kernel vs shapely, and a property test driving into walls."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from ray_reference import footprint_overlap_area
from sim_worlds import office_world

from slam_predict.sim import OdomConfig, RobotOverrides, SimConfig, Simulator
from slam_predict.sim.raycast import GridFrame, footprint_collides
from slam_predict.world.model import LaserSpec, World

QUIET = LaserSpec(rate_hz=1e-3)


def test_kernel_agrees_with_shapely_on_random_poses():
    world = office_world(4, thin=True, size_px=(120, 160), res=0.05)
    frame = GridFrame.of_world(world)
    rng = np.random.default_rng(4)
    (x0, y0), (x1, y1) = world.cell_to_world([world.shape[0] - 1, 0]), world.cell_to_world(
        [0, world.shape[1] - 1])
    hits = 0
    for _ in range(1500):
        x, y = rng.uniform(x0, x1), rng.uniform(y0, y1)
        yaw, side = rng.uniform(-math.pi, math.pi), rng.uniform(0.05, 0.6)
        area = footprint_overlap_area(world.occupied, frame, x, y, yaw, side)
        got = footprint_collides(world.occupied, frame.x_left, frame.y_top, frame.resolution,
                                 x, y, yaw, side)
        if area > 1e-12:
            assert got, (x, y, yaw, side, area)
        elif area == 0.0:
            assert not got, (x, y, yaw, side)
        hits += got
    assert 100 < hits < 1400  # both outcomes exercised


def test_footprint_leaving_the_map_collides():
    occ = np.zeros((20, 20), dtype=bool)
    world = World("open", occ, 0.1)
    f = GridFrame.of_world(world)
    assert not footprint_collides(occ, f.x_left, f.y_top, f.resolution, 0.0, 0.0, 0.3, 0.5)
    assert footprint_collides(occ, f.x_left, f.y_top, f.resolution, 0.9, 0.0, 0.0, 0.3)
    # touching the border exactly is not an overlap
    assert not footprint_collides(occ, f.x_left, f.y_top, f.resolution, 0.85, 0.0, 0.0, 0.3)


def _world(seed: int, res: float) -> World:
    rows, cols = int(6.0 / res), int(8.0 / res)
    world = office_world(seed, thin=seed % 2 == 0, size_px=(rows, cols), res=res)
    return world


def _start(world: World, rng: np.random.Generator, side: float) -> np.ndarray:
    frame = GridFrame.of_world(world)
    free = np.argwhere(~world.occupied)
    for _ in range(2000):
        r, c = free[rng.integers(len(free))]
        x, y = world.cell_to_world((r, c))
        yaw = rng.uniform(-math.pi, math.pi)
        if not footprint_collides(world.occupied, frame.x_left, frame.y_top, frame.resolution,
                                  x, y, yaw, side):
            return np.array([x, y, yaw])
    pytest.skip("no collision-free start found")


commands = st.lists(st.tuples(st.floats(-1.0, 1.0), st.floats(-2.0, 2.0), st.integers(1, 25)),
                    min_size=1, max_size=8)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 50), res=st.sampled_from([0.025, 0.05, 0.1]),
       integrator=st.sampled_from(["exact", "stage"]), side=st.floats(0.1, 0.6),
       accel=st.sampled_from([0.0, 1.5]), plan=commands)
def test_driving_never_overlaps_an_occupied_cell(seed, res, integrator, side, accel, plan):
    world = _world(seed, res)
    rng = np.random.default_rng(seed)
    world = world.replace(start_pose=_start(world, rng, side), laser=QUIET)
    config = SimConfig(integrator=integrator, odom=OdomConfig(model="none"),
                       robot=RobotOverrides(footprint_side=side, max_vel_x=1.0,
                                            max_vel_theta=2.0, max_acc_x=accel))
    sim = Simulator(world, config, rng)
    frame = GridFrame.of_world(world)
    for v, w, n in plan:
        for _ in range(n):
            before = sim.true_pose.copy()
            state = sim.step(v, w)
            area = footprint_overlap_area(world.occupied, frame, *state.true_pose, side)
            assert area <= 1e-12, (state.true_pose, area)
            if state.stalled:
                np.testing.assert_array_equal(state.true_pose, before)


def test_drive_into_wall_head_on_stalls_short_of_it():
    world = office_world(0, size_px=(120, 160), res=0.05).replace(laser=QUIET)
    frame = GridFrame.of_world(world)
    # start in free space and drive east until stalled
    start = _start(world, np.random.default_rng(1), 0.3)
    world = world.replace(start_pose=np.array([start[0], start[1], 0.0]))
    sim = Simulator(world, SimConfig(odom=OdomConfig(model="none")), np.random.default_rng(0))
    for _ in range(400):
        state = sim.step(1.0, 0.0)
        if state.stalled:
            break
    assert state.stalled
    assert footprint_overlap_area(world.occupied, frame, *state.true_pose, 0.3) == 0.0
    moved = state.true_pose.copy()
    moved[0] += 0.1 + 1e-6  # the refused step would have overlapped
    assert footprint_collides(world.occupied, frame.x_left, frame.y_top, 0.05, *moved, 0.3)
