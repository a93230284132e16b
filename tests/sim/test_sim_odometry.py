"""Odometry error models: statistics over 1,000 seeds, Stage's fixed biases, stall behaviour."""
from __future__ import annotations

import math

import numpy as np
import pytest
from sim_worlds import box_world

from slam_predict.geometry import ominus, wrap_angle
from slam_predict.sim import OdomConfig, RobotOverrides, SimConfig, Simulator
from slam_predict.sim.odometry import UniformPerRun, make_odometry, world_error
from slam_predict.world.model import LaserSpec, RobotSpec

SEEDS = 1000
E = (0.01, 0.01, math.radians(2.0))  # realistic: m/m, m/m, rad/rad
NO_RAMPS = RobotOverrides(max_vel_x=1.0, max_vel_theta=1.0, max_acc_x=0.0, max_acc_theta=0.0)


def world(start=(0.0, 0.0, 0.0), res=0.5):
    return box_world(100.0, 100.0, res=res, start=start, laser=LaserSpec(rate_hz=1e-3))


WORLD = world()


def odom_error_after(model: OdomConfig, seed: int, v: float, w: float, steps: int,
                     collisions: bool = False) -> np.ndarray:
    """Odometry error (odom ⊖ truth-relative-to-start, in the start frame) after a run."""
    config = SimConfig(odom=model, robot=NO_RAMPS, collisions=collisions)
    sim = Simulator(WORLD, config, np.random.default_rng(seed))
    for _ in range(steps):
        state = sim.step(v, w)
    truth = ominus(state.true_pose, WORLD.start_pose)
    err = state.odom_pose - truth
    err[2] = float(wrap_angle(err[2]))
    return err


def errors(model: OdomConfig, v: float, w: float, steps: int) -> np.ndarray:
    return np.array([odom_error_after(model, s, v, w, steps) for s in range(SEEDS)])


def check_uniform(samples: np.ndarray, bound: float):
    """Uniform in [-bound, bound]: inside the bounds, zero mean, std bound/√3."""
    assert np.all(np.abs(samples) <= bound * (1 + 1e-9))
    assert abs(samples.mean()) < 4 * bound / math.sqrt(3 * SEEDS)
    assert samples.std() == pytest.approx(bound / math.sqrt(3), rel=0.08)
    assert np.abs(samples).max() > 0.95 * bound  # the draw reaches its bounds


def test_uniform_per_run_growth_per_metre():
    """Straight 2 m: x and y errors e_x·L and e_y·L, uniform over runs."""
    err = errors(OdomConfig(model="uniform_per_run", error=E), 1.0, 0.0, 20)
    check_uniform(err[:, 0], E[0] * 2.0)
    check_uniform(err[:, 1], E[1] * 2.0)
    np.testing.assert_allclose(err[:, 2], 0.0, atol=1e-12)


def test_uniform_per_run_growth_per_radian():
    """In-place rotation by 2 rad: heading error e_θ·2, uniform over runs; no translation."""
    err = errors(OdomConfig(model="uniform_per_run", error=E), 0.0, 1.0, 20)
    check_uniform(err[:, 2], E[2] * 2.0)
    np.testing.assert_allclose(err[:, :2], 0.0, atol=1e-12)


def test_uniform_per_run_metadata_records_the_draw():
    sims = [Simulator(WORLD, SimConfig(odom=OdomConfig(error=E)), np.random.default_rng(s))
            for s in range(SEEDS)]
    bias = np.array([s.odom_error["bias"] for s in sims])
    assert sims[0].odom_error["model"] == "uniform_per_run"
    assert sims[0].odom_error["bound"] == pytest.approx(list(E))
    for axis in range(3):
        check_uniform(bias[:, axis], E[axis])
    again = Simulator(WORLD, SimConfig(odom=OdomConfig(error=E)), np.random.default_rng(7))
    assert again.odom_error == sims[7].odom_error  # seeded: reproducible


def test_uniform_bounds_default_to_world_odom_error():
    robot = RobotSpec(odom_error=(0.05, 0.02, 0.0, 0.1))
    w = WORLD.replace(robot=robot)
    sim = Simulator(w, SimConfig(), np.random.default_rng(0))
    assert sim.odom_error["bound"] == pytest.approx([0.05, 0.02, 0.1])


def test_gaussian_per_step_random_walk_growth():
    k = (0.02, 0.01, 0.03, 0.0)
    model = OdomConfig(model="gaussian_per_step", gaussian=k)
    straight = errors(model, 1.0, 0.0, 20)  # 2 m
    for axis, density in ((0, k[0]), (1, k[1])):
        expected = density * math.sqrt(2.0)
        assert abs(straight[:, axis].mean()) < 4 * expected / math.sqrt(SEEDS)
        assert straight[:, axis].std() == pytest.approx(expected, rel=0.1)
    np.testing.assert_allclose(straight[:, 2], 0.0, atol=1e-12)  # k_θs = 0
    turn = errors(model, 0.0, 1.0, 20)  # 2 rad
    expected = k[2] * math.sqrt(2.0)
    assert abs(turn[:, 2].mean()) < 4 * expected / math.sqrt(SEEDS)
    assert turn[:, 2].std() == pytest.approx(expected, rel=0.1)
    np.testing.assert_allclose(turn[:, :2], 0.0, atol=1e-12)


def test_gaussian_heading_noise_per_metre():
    """k_θs alone: heading error std k_θs·√L after L m, which bends the odometry sideways."""
    k = (0.0, 0.0, 0.0, 0.004)
    err = errors(OdomConfig(model="gaussian_per_step", gaussian=k), 1.0, 0.0, 25)
    assert err[:, 2].std() == pytest.approx(0.004 * math.sqrt(2.5), rel=0.1)
    assert abs(err[:, 2].mean()) < 4 * 0.004 * math.sqrt(2.5) / math.sqrt(SEEDS)
    assert np.abs(err[:, 1]).max() > 0


def test_fixed_model_is_stage_constant_bias():
    e = (0.03, 0.03, -0.02)
    straight = [odom_error_after(OdomConfig(model="fixed", error=e), s, 1.0, 0.0, 30)
                for s in range(3)]
    for err in straight:
        np.testing.assert_allclose(err, [0.03 * 3.0, 0.0, 0.0], atol=1e-12)  # e_y inert
    turn = odom_error_after(OdomConfig(model="fixed", error=e), 0, 0.0, 1.0, 20)
    np.testing.assert_allclose(turn, [0.0, 0.0, -0.02 * 2.0], atol=1e-12)


def test_fixed_model_uses_world_file_values_with_degrees_converted():
    # a world file saying odom_error [0.03 0.03 0.00 0.05] gives yaw 0.05° → 8.7e-4 rad
    w = WORLD.replace(robot=RobotSpec(odom_error=(0.03, 0.03, 0.0, math.radians(0.05))))
    sim = Simulator(w, SimConfig(odom=OdomConfig(model="fixed")), np.random.default_rng(0))
    assert sim.odom_error["bias"] == pytest.approx([0.03, 0.03, 8.7266e-4], rel=1e-4)


def test_none_model_is_exact():
    err = odom_error_after(OdomConfig(model="none"), 0, 0.7, 0.3, 50)
    np.testing.assert_allclose(err, 0.0, atol=1e-12)


def test_odometry_keeps_integrating_while_stalled():
    w = world(start=(48.0, 0.0, 0.0), res=0.05)  # inner east wall at x = 49.9
    config = SimConfig(odom=OdomConfig(model="none"), robot=NO_RAMPS)
    sim = Simulator(w, config, np.random.default_rng(0))
    for _ in range(40):
        state = sim.step(1.0, 0.0)
    assert state.stalled
    assert state.true_pose[0] < 49.9 - 0.15 + 1e-9
    assert state.velocity == (1.0, 0.0)  # Stage does not zero the velocity
    assert state.odom_pose[0] == pytest.approx(4.0)  # but odometry counted all 40 steps


def test_world_error_reads_stage_four_tuple():
    assert world_error((0.1, 0.2, 0.3, 0.4)) == (0.1, 0.2, 0.4)
    with pytest.raises(ValueError):
        world_error((1.0, 2.0))


def test_make_odometry_draws_three_uniforms_once():
    rng = np.random.default_rng(3)
    model = make_odometry(OdomConfig(), (0.1, 0.1, 0.1), rng)
    assert isinstance(model, UniformPerRun)
    expected = np.random.default_rng(3).uniform(-1, 1, 3) * 0.1
    np.testing.assert_allclose(model.bias, expected)
    assert model.perturb((1.0, 0.0, 0.0), rng) == pytest.approx((1 + expected[0], expected[1], 0))
