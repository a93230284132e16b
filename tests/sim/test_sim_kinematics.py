"""Kinematics: exact integrator vs analytic motion, Stage integrator vs Stage's formulas."""
from __future__ import annotations

import math

import numpy as np
import pytest
from sim_worlds import box_world

from slam_predict.geometry import compose, wrap_angle
from slam_predict.sim import OdomConfig, RobotOverrides, SimConfig, Simulator
from slam_predict.sim.kinematics import VelocityLimits, arc_delta, limit_velocity
from slam_predict.world.model import LaserSpec

NO_RAMPS = RobotOverrides(max_vel_x=2.0, max_vel_theta=3.0, max_acc_x=0.0, max_acc_theta=0.0)
QUIET_LASER = LaserSpec(rate_hz=1e-3)  # no scans: these tests are about motion
NO_ODOM_NOISE = OdomConfig(model="none")


def make_sim(integrator="exact", odom=NO_ODOM_NOISE, start=(1.0, -2.0, 0.4),
             robot=NO_RAMPS, collisions=False, seed=0) -> Simulator:
    world = box_world(400.0, 400.0, res=0.5, start=start, laser=QUIET_LASER)
    config = SimConfig(integrator=integrator, odom=odom, robot=robot, collisions=collisions)
    return Simulator(world, config, np.random.default_rng(seed))


def run(sim: Simulator, v: float, w: float, steps: int):
    for _ in range(steps):
        state = sim.step(v, w)
    return state


def test_straight_line_matches_analytic():
    sim = make_sim()
    state = run(sim, 0.7, 0.0, 200)
    x0, y0, th0 = 1.0, -2.0, 0.4
    t = 200 * 0.1
    np.testing.assert_allclose(state.true_pose, [x0 + 0.7 * t * math.cos(th0),
                                                 y0 + 0.7 * t * math.sin(th0), th0], atol=1e-6)
    assert state.t == pytest.approx(t)


def test_in_place_turn_matches_analytic():
    sim = make_sim()
    state = run(sim, 0.0, -1.3, 77)
    np.testing.assert_allclose(state.true_pose[:2], [1.0, -2.0], atol=1e-12)
    assert state.true_pose[2] == pytest.approx(float(wrap_angle(0.4 - 1.3 * 7.7)), abs=1e-6)


@pytest.mark.parametrize("v,w", [(0.8, 0.5), (-0.4, 1.1), (1.0, -0.05), (0.3, 1e-7)])
def test_arc_matches_analytic(v, w):
    sim = make_sim()
    steps = 150
    state = run(sim, v, w, steps)
    x0, y0, th0 = 1.0, -2.0, 0.4
    t = steps * 0.1
    if abs(w) > 1e-6:
        x = x0 + v / w * (math.sin(th0 + w * t) - math.sin(th0))
        y = y0 - v / w * (math.cos(th0 + w * t) - math.cos(th0))
    else:  # second-order expansion of the same formulas
        x = x0 + v * t * math.cos(th0) - 0.5 * v * w * t * t * math.sin(th0)
        y = y0 + v * t * math.sin(th0) + 0.5 * v * w * t * t * math.cos(th0)
    np.testing.assert_allclose(state.true_pose[:2], [x, y], atol=1e-6)
    assert float(wrap_angle(state.true_pose[2] - (th0 + w * t))) == pytest.approx(0.0, abs=1e-6)


def test_odometry_without_error_is_truth_relative_to_start():
    sim = make_sim(odom=OdomConfig(model="none"))
    for k in range(300):
        state = sim.step(0.9 * math.sin(k / 20.0), 0.8 * math.cos(k / 15.0))
    np.testing.assert_allclose(compose(sim.world.start_pose, state.odom_pose), state.true_pose,
                               atol=1e-9)


def test_stage_integrator_matches_stage_formulas():
    """Stage Move(): translate along the OLD heading, then rotate. Stage odometry: yaw first
    (with (1+e_a)), then translate along the NEW heading with (1+e_x)."""
    e = (0.02, 0.03, 0.01)
    sim = make_sim("stage", OdomConfig(model="fixed", error=e))
    rng = np.random.default_rng(4)
    x, y, th = 1.0, -2.0, 0.4
    ox = oy = oth = 0.0
    dt = 0.1
    for _ in range(250):
        v, w = rng.uniform(-1.5, 1.5), rng.uniform(-2.0, 2.0)
        state = sim.step(v, w)
        x, y, th = x + v * dt * math.cos(th), y + v * dt * math.sin(th), th + w * dt
        oth += w * dt * (1 + e[2])
        ox += v * dt * (1 + e[0]) * math.cos(oth)
        oy += v * dt * (1 + e[0]) * math.sin(oth)
        np.testing.assert_allclose(state.velocity, (v, w))
    np.testing.assert_allclose(state.true_pose[:2], [x, y], atol=1e-9)
    assert float(wrap_angle(state.true_pose[2] - th)) == pytest.approx(0.0, abs=1e-9)
    np.testing.assert_allclose(state.odom_pose[:2], [ox, oy], atol=1e-9)
    assert float(wrap_angle(state.odom_pose[2] - oth)) == pytest.approx(0.0, abs=1e-9)


def test_stage_odometry_differs_slightly_from_truth_even_without_error():
    sim = make_sim("stage", OdomConfig(model="none"))
    state = run(sim, 1.0, 1.0, 30)
    drift = np.hypot(*(compose(sim.world.start_pose, state.odom_pose) - state.true_pose)[:2])
    assert 1e-4 < drift < 0.2


def test_velocity_clamped_to_bounds():
    sim = make_sim(robot=RobotOverrides(max_vel_x=1.0, max_vel_theta=math.pi / 2,
                                        max_acc_x=0.0, max_acc_theta=0.0))
    assert sim.step(5.0, -9.0).velocity == (1.0, -math.pi / 2)
    assert sim.step(-5.0, 9.0).velocity == (-1.0, math.pi / 2)


def test_acceleration_ramp():
    sim = make_sim(robot=RobotOverrides(max_vel_x=1.0, max_acc_x=1.5, max_acc_theta=2.0))
    speeds = [sim.step(1.0, 1.0).velocity for _ in range(10)]
    np.testing.assert_allclose([s[0] for s in speeds[:7]],
                               [0.15, 0.3, 0.45, 0.6, 0.75, 0.9, 1.0])
    np.testing.assert_allclose([s[1] for s in speeds[:6]], [0.2, 0.4, 0.6, 0.8, 1.0, 1.0])
    stops = [sim.step(0.0, 0.0).velocity[0] for _ in range(8)]
    np.testing.assert_allclose(stops, [0.85, 0.7, 0.55, 0.4, 0.25, 0.1, 0.0, 0.0], atol=1e-12)


def test_limit_velocity_unlimited_acceleration_is_immediate():
    limits = VelocityLimits(1.0, 1.0, 0.0, 0.0)
    assert limit_velocity(0.5, -0.25, 0.0, 0.0, limits, 0.1) == (0.5, -0.25)


def test_arc_delta_small_angle_is_continuous():
    a = arc_delta(1.0, 1e-5, 0.1)
    b = arc_delta(1.0, 2e-3, 0.1)
    assert a[0] == pytest.approx(0.1, abs=1e-12) and a[1] == pytest.approx(5e-8, rel=1e-6)
    assert b[1] == pytest.approx(0.1 * (1 - math.cos(2e-4)) / 2e-4, rel=1e-9)
