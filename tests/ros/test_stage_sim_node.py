"""stage_sim node logic without a ROS master: watchdog, messages per step, pacing, lockstep."""
from __future__ import annotations

import threading
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("nav_msgs.msg", reason="ROS 1 python messages not installed")

from geometry_msgs.msg import Twist  # noqa: E402

from slam_predict.geometry import compose  # noqa: E402
from slam_predict.ros.conversions.geometry import (odometry_from_ros,  # noqa: E402
                                                   transform_from_ros)
from slam_predict.ros.stage_sim_node import NodeSettings, StageSim  # noqa: E402
from slam_predict.sim import OdomConfig, SimConfig, Simulator  # noqa: E402
from slam_predict.world.load import load_plan  # noqa: E402

ROOM = Path(__file__).resolve().parents[1] / "data" / "stage_sim_room.world"


class FakePublisher:
    def __init__(self):
        self.messages = []

    def publish(self, msg):
        self.messages.append(msg)


class FakeBroadcaster:
    def __init__(self):
        self.batches = []

    def sendTransform(self, transforms):  # noqa: N802 (tf2_ros API)
        self.batches.append(transforms)


class FakeRospy:
    def __init__(self):
        self.shutdown = False

    def is_shutdown(self):
        return self.shutdown


def make_node(**settings) -> StageSim:
    world = load_plan(ROOM)
    sim = Simulator(world, SimConfig(odom=OdomConfig(model="none")), np.random.default_rng(0))
    node = StageSim(sim, NodeSettings(**settings), FakeRospy())
    node._pubs = {name: FakePublisher() for name in ("clock", "odom", "truth", "scan")}
    node._tf = FakeBroadcaster()
    return node


def twist(v, w):
    msg = Twist()
    msg.linear.x, msg.angular.z = v, w
    return msg


def test_each_step_publishes_clock_tf_odom_truth_scan():
    node = make_node(laser_z=0.3)
    node.on_cmd_vel(twist(0.5, 0.2))
    node.step()
    node.step()
    pubs = node._pubs
    assert [m.clock.to_sec() for m in pubs["clock"].messages] == pytest.approx([0.1, 0.2])
    assert len(pubs["scan"].messages[-1].ranges) == 541
    odom = odometry_from_ros(pubs["odom"].messages[-1])
    truth = odometry_from_ros(pubs["truth"].messages[-1])
    assert (odom.frame_id, odom.child_frame_id) == ("odom", "base_footprint")
    assert truth.frame_id == "odom"  # stageros' label for the world-frame ground truth
    np.testing.assert_allclose(compose(node.sim.world.start_pose, odom.pose), truth.pose,
                               atol=1e-12)
    assert odom.twist == pytest.approx((0.3, 0.0, 0.2))  # ramped at 1.5 m/s²
    assert truth.twist[0] == pytest.approx(0.3 * np.cos(truth.pose[2] - 0.01), rel=0.05)
    chain = [transform_from_ros(t) for t in node._tf.batches[-1]]
    assert [(c.parent, c.child) for c in chain] == [
        ("odom", "base_footprint"), ("base_footprint", "base_link"),
        ("base_link", "base_laser_link")]
    assert chain[2].z == 0.3 and all(c.stamp == pytest.approx(0.2) for c in chain)


def test_watchdog_zeroes_the_command_after_timeout():
    node = make_node(watchdog_timeout=0.2)
    node.on_cmd_vel(twist(1.0, 0.0))
    commands = []
    for _ in range(4):
        commands.append(node.command())
        node.step()
    assert commands == [(1.0, 0.0), (1.0, 0.0), (0.0, 0.0), (0.0, 0.0)]
    off = make_node(watchdog_timeout=0.0)
    off.on_cmd_vel(twist(1.0, 0.0))
    for _ in range(30):
        off.step()
    assert off.command() == (1.0, 0.0)


def test_reset_positions_restores_the_start():
    node = make_node()
    node.on_cmd_vel(twist(1.0, 0.5))
    for _ in range(10):
        node.step()
    node.on_reset(None)
    np.testing.assert_array_equal(node.sim.true_pose, node.sim.world.start_pose)
    assert node.sim.t == 0.0 and node.command() == (0.0, 0.0)


def test_speedup_paces_in_wall_time():
    node = make_node(speedup=10.0)
    start = time.monotonic()
    node.run(max_steps=10)  # 1 s of sim time at 10x → ~0.09 s
    elapsed = time.monotonic() - start
    assert 0.08 <= elapsed < 1.0
    assert node.sim.t == pytest.approx(1.0)


def test_lockstep_waits_for_cmd_vel_or_timeout():
    node = make_node(speedup=0.0, lockstep=True, lockstep_timeout=0.05)
    start = time.monotonic()
    node.run(max_steps=6)  # nobody commands: each step waits the full timeout
    assert time.monotonic() - start >= 0.25

    node = make_node(speedup=0.0, lockstep=True, lockstep_timeout=5.0)
    stop = threading.Event()

    def controller():  # answers every published scan with a command
        seen = 0
        while not stop.is_set():
            if len(node._pubs["scan"].messages) > seen:
                seen = len(node._pubs["scan"].messages)
                node.on_cmd_vel(twist(0.2, 0.0))
            time.sleep(0.001)

    thread = threading.Thread(target=controller)
    thread.start()
    start = time.monotonic()
    node.run(max_steps=20)
    stop.set()
    thread.join()
    assert time.monotonic() - start < 4.0  # never waited for the 5 s timeout
    assert node.sim.velocity[0] == pytest.approx(0.2)
