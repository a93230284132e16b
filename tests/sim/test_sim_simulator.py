"""Simulator: config loading, laser rate/timing/mounting/noise, determinism, reset."""
from __future__ import annotations

import math

import numpy as np
import pytest
from ray_reference import slab_ranges
from sim_worlds import box_world, office_world

from slam_predict.config import from_dict, load_config, to_dict
from slam_predict.errors import InputError
from slam_predict.geometry import compose
from slam_predict.sim import LaserOverrides, OdomConfig, SimConfig, SimState, Simulator
from slam_predict.sim.raycast import GridFrame


def sim_in(world, seed=0, **config) -> Simulator:
    return Simulator(world, SimConfig(**config), np.random.default_rng(seed))


def test_robot_yaml_loads_the_thesis_settings(root):
    config = load_config(SimConfig, root / "config" / "robot.yaml", "sim")
    assert config.odom.model == "uniform_per_run"
    assert config.odom.error == pytest.approx((0.01, 0.01, math.radians(2.0)), rel=1e-5)
    assert config.robot.footprint_side == 0.3 and config.robot.max_acc_x == 1.5
    assert config.laser.samples == 541 and config.laser.fov == pytest.approx(1.5 * math.pi)
    assert from_dict(SimConfig, to_dict(config)) == config


@pytest.mark.parametrize("data,message", [
    ({"integrater": "exact"}, "did you mean 'integrator'"),
    ({"integrator": "euler"}, "integrator must be one of exact, stage"),
    ({"ranger_model": "gazebo"}, "ranger_model must be one of exact, stage"),
    ({"stage_resolution": 0.0}, "'stage_resolution' must be > 0, got 0.0"),
    ({"odom": {"model": "uniform"}}, "odom model must be one of"),
    ({"laser": {"range_max": "far"}}, "must be a number"),
    ({"scan_timing": "late"}, "scan_timing must be one of"),
    ({"laser": {"samples": 0}}, "'laser.samples' must be ≥ 1, got 0"),
    ({"laser": {"range_max": 0.0}}, "'laser.range_max' must be > 0, got 0.0"),
    ({"robot": {"max_vel_x": -1.0}}, "'robot.max_vel_x' must be ≥ 0, got -1.0"),
])
def test_bad_config_is_one_line_input_error(data, message):
    with pytest.raises(InputError) as info:
        from_dict(SimConfig, data, "robot.yaml")
    assert message in str(info.value) and "robot.yaml" in str(info.value)
    assert "\n" not in str(info.value)


def test_overrides_replace_world_values_and_none_keeps_them():
    world = box_world(10, 10)
    sim = sim_in(world, laser=LaserOverrides(samples=181, range_max=12.0))
    assert sim.laser.samples == 181 and sim.laser.range_max == 12.0
    assert sim.laser.fov == world.laser.fov and sim.robot == world.robot
    assert sim.laser_angles.shape == (181,)
    assert sim.laser_angles[0] == pytest.approx(-world.laser.fov / 2)


def test_scan_every_step_at_10_hz_with_541_float32_ranges():
    sim = sim_in(box_world(10, 10))
    states = [sim.step(0.2, 0.1) for _ in range(20)]
    assert all(s.scan is not None for s in states)
    assert states[0].scan.dtype == np.float32 and states[0].scan.shape == (541,)
    assert [s.t for s in states[:3]] == pytest.approx([0.1, 0.2, 0.3])


def test_laser_rate_below_step_rate_skips_steps():
    sim = sim_in(box_world(10, 10), laser=LaserOverrides(rate_hz=4.0))
    taken = [sim.step(0.0, 0.0).scan is not None for _ in range(20)]
    assert sum(taken) == 8  # 2 s at 4 Hz
    assert taken[:5] == [False, False, True, False, True]


def test_scan_timing_after_and_before_move():
    world = box_world(10, 10)
    after = sim_in(world, odom=OdomConfig(model="none"))
    before = sim_in(world, odom=OdomConfig(model="none"), scan_timing="before_move")
    s_after = [after.step(0.5, 0.2) for _ in range(5)][-1]
    s_before = [before.step(0.5, 0.2) for _ in range(5)]
    np.testing.assert_array_equal(s_after.scan_true_pose, s_after.true_pose)
    np.testing.assert_array_equal(s_before[-1].scan_true_pose, s_before[-2].true_pose)
    np.testing.assert_array_equal(s_before[-1].scan, before.scan_from(s_before[-2].true_pose))


def test_scan_is_taken_from_the_mounted_laser_pose():
    world = office_world(2, size_px=(120, 160), res=0.05)
    free = np.argwhere(~world.occupied)
    world = world.replace(start_pose=world.cell_to_world(free[len(free) // 3]).tolist() + [0.7])
    mount = (0.12, -0.05, 0.3)
    sim = sim_in(world, laser=LaserOverrides(pose=mount, range_max=30.0))
    state = sim.step(0.0, 0.0)
    laser = compose(state.true_pose, mount)
    expected = slab_ranges(world.occupied, GridFrame.of_world(world), *laser,
                           sim.laser_angles, 30.0)
    np.testing.assert_allclose(state.scan, expected, atol=2e-5)
    np.testing.assert_array_equal(sim.laser_pose, mount)


def test_range_noise_is_off_by_default_and_gaussian_when_set():
    world = box_world(10, 10)
    clean = sim_in(world).step(0.0, 0.0).scan
    noisy = np.array([sim_in(world, seed=s, laser=LaserOverrides(noise_std=0.02))
                      .step(0.0, 0.0).scan for s in range(200)])
    diff = noisy - clean
    assert abs(diff.mean()) < 0.001
    assert diff.std() == pytest.approx(0.02, rel=0.05)
    again = sim_in(world, laser=LaserOverrides(noise_std=0.0)).step(0.0, 0.0).scan
    np.testing.assert_array_equal(again, clean)


def test_same_seed_same_run_and_reset_restores_start():
    world = office_world(1, size_px=(120, 160), res=0.05)
    world = world.replace(start_pose=world.cell_to_world((60, 20)).tolist() + [0.0])
    runs = []
    for _ in range(2):
        sim = sim_in(world, seed=42, odom=OdomConfig(model="gaussian_per_step"))
        runs.append([sim.step(0.6, 0.3 * math.sin(k / 7)) for k in range(60)])
    for a, b in zip(*runs, strict=False):
        np.testing.assert_array_equal(a.odom_pose, b.odom_pose)
        np.testing.assert_array_equal(a.scan, b.scan)
    sim.reset()
    assert sim.t == 0.0 and sim.velocity == (0.0, 0.0)
    np.testing.assert_array_equal(sim.true_pose, world.start_pose)
    np.testing.assert_array_equal(sim.odom_pose, np.zeros(3))


def test_state_arrays_are_copies():
    sim = sim_in(box_world(10, 10))
    state = sim.step(0.5, 0.0)
    assert isinstance(state, SimState)
    state.true_pose[0] += 5.0
    assert sim.true_pose[0] != state.true_pose[0]


def test_stalled_clears_when_the_robot_moves_away():
    world = box_world(4, 4, start=(1.6, 0.0, 0.0))  # east wall at x = 1.9
    sim = sim_in(world, odom=OdomConfig(model="none"))
    states = [sim.step(1.0, 0.0) for _ in range(10)]
    assert states[-1].stalled
    sim.step(0.0, 0.0)  # Stage: the robot is not stalled when not moving
    for _ in range(15):
        state = sim.step(-1.0, 0.0)
    assert not state.stalled and state.true_pose[0] < 1.5
