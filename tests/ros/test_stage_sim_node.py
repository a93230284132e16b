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
from slam_predict.ros.conversions.geometry import odometry_from_ros, transform_from_ros  # noqa: E402
from slam_predict.ros.stage_sim_node import StageSim  # noqa: E402
from slam_predict.ros.stage_sim_params import NodeSettings  # noqa: E402
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

    assert run_beside(node, controller, stop, 20) < 4.0  # never waited for the 5 s timeout
    assert node.sim.velocity[0] == pytest.approx(0.2)


def run_beside(node, other_nodes, stop, steps):
    """Run ``steps`` simulator steps while ``other_nodes`` (a loop until ``stop`` is set) plays
    the other nodes in a thread; returns the wall seconds the steps took."""
    thread = threading.Thread(target=other_nodes)
    thread.start()
    start = time.monotonic()
    node.run(max_steps=steps)
    elapsed = time.monotonic() - start
    stop.set()
    thread.join()
    return elapsed


class FakeScanPublisher(FakePublisher):
    def get_num_connections(self):
        return 1


def ack(t):
    import rospy
    from std_msgs.msg import Time
    return Time(rospy.Time.from_sec(t))


def test_lockstep_acks_wait_for_every_node_before_each_step():
    """A scan consumer must ack the newest scan, a periodic node its tick, before the next step;
    the sim never runs ahead of the slowest node."""
    acks = (("/slam/sim_ack", None), ("/nav/sim_ack", 0.0))
    node = make_node(speedup=0.0, lockstep=True, lockstep_acks=acks, lockstep_ack_timeout=5.0)
    node._pubs["scan"] = FakeScanPublisher()
    stop = threading.Event()
    log, ahead = [], []

    def nodes():  # slam acks each scan; nav ticks at 0.2 s multiples, acking next tick - 1 ms
        node.on_ack(ack(0.0), "/slam/sim_ack")
        node.on_ack(ack(0.2 - 1e-3), "/nav/sim_ack")
        scans = 0
        next_tick = 0.2
        while not stop.is_set():
            t = node.sim.t
            log.append(t)
            if len(node._pubs["scan"].messages) > scans:
                scans = len(node._pubs["scan"].messages)
                stamp = node._pubs["scan"].messages[-1].header.stamp.to_sec()
                time.sleep(0.002)  # "processing": the simulator must not move meanwhile
                ahead.append(node.sim.t - stamp)
                node.on_ack(ack(stamp), "/slam/sim_ack")
            if t >= next_tick - 1e-6:
                time.sleep(0.002)
                ahead.append(node.sim.t - t)
                next_tick = (round(t / 0.2) + 1) * 0.2
                node.on_ack(ack(next_tick - 1e-3), "/nav/sim_ack")
            time.sleep(0.0005)

    assert run_beside(node, nodes, stop, 30) < 4.0  # never hit the 5 s timeout
    assert node.sim.t == pytest.approx(3.0)
    assert not node._late
    assert len(ahead) >= 40 and max(ahead) < 1e-9   # it waited for every scan and tick
    assert node._acks["/nav/sim_ack"] >= 3.0 - 1e-6 - 0.2


def test_lockstep_ack_timeout_steps_on_and_names_the_laggard(caplog):
    """A silent node costs one timeout, not one per step (a dead node must not slow the run to
    a crawl); once it acks again the simulator waits for it again."""
    acks = (("/slow/sim_ack", 0.0),)
    node = make_node(speedup=0.0, lockstep=True, lockstep_acks=acks, lockstep_ack_timeout=0.3)
    node._pubs["scan"] = FakeScanPublisher()
    node.on_ack(ack(0.0), "/slow/sim_ack")   # its first ack, then silence
    start = time.monotonic()
    node.run(max_steps=10)   # step 1 (t = 0) is acked; step 2 waits 0.3 s, then no more waits
    wall = time.monotonic() - start
    assert 0.3 <= wall < 0.6
    assert node.sim.t == pytest.approx(1.0)
    assert node._late == {"/slow/sim_ack"}
    assert "/slow/sim_ack" in caplog.text
    node.on_ack(ack(1.0), "/slow/sim_ack")   # back: acked the current step
    assert not node._late
    start = time.monotonic()
    node.run(max_steps=2)   # the first step is acked, the second waits out the timeout again
    assert time.monotonic() - start >= 0.3
    assert node._late == {"/slow/sim_ack"}


def test_lockstep_acks_parameter_parsing():
    from slam_predict.errors import InputError
    from slam_predict.ros.stage_sim_params import ack_list

    assert ack_list("[[/a/sim_ack, scan], [/b/sim_ack, 0.1], ]") == (("/a/sim_ack", None),
                                                                      ("/b/sim_ack", 0.1))
    assert ack_list([]) == () and ack_list("") == ()
    assert ack_list(["/c"]) == (("/c", 0.0),)
    for bad in ("[[/a, -1]]", "[[/a, soon]]", "[[1, 2]]", "[[/a, 1, 2]]"):
        with pytest.raises(InputError, match="lockstep_acks"):
            ack_list(bad)


def test_shutdown_wakes_a_lockstep_wait_at_once():
    """A node asked to shut down (orchestrator's ordered end of a run) must not sit out the
    ack timeout: its ack subscriptions are closed, so the acks never come."""
    import threading
    import time

    acks = (("/slam_gmapping/sim_ack", None),)
    node = make_node(speedup=0.0, lockstep=True, lockstep_acks=acks, lockstep_ack_timeout=20.0)
    node._last_scan_t = 0.1
    waiter = threading.Thread(target=node.wait_for_acks)
    waiter.start()
    time.sleep(0.2)
    assert waiter.is_alive()          # waiting for the ack
    started = time.monotonic()
    node.wake()   # rospy calls on_shutdown hooks without arguments, before is_shutdown() is true
    waiter.join(5.0)
    assert not waiter.is_alive() and time.monotonic() - started < 1.0
    assert node.stopped()
