"""move_base node logic without a master: goal handles and actionlib's lock order."""
from __future__ import annotations

import threading
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("move_base_msgs.msg", reason="ROS 1 python messages not installed")

from slam_predict.nav.config import load_nav_config  # noqa: E402
from slam_predict.ros.move_base_node import MoveBaseNode  # noqa: E402

CONFIG = Path(__file__).resolve().parents[2] / "config"


class FakeRospy:
    def __init__(self):
        self.t = 1.0

    def get_time(self):
        return self.t

    def is_shutdown(self):
        return False

    def Time(self, _t=0):  # noqa: N802 (rospy API)
        return 0


class FakePublisher:
    def __init__(self):
        self.messages = []

    def publish(self, msg):
        self.messages.append(msg)

    def get_num_connections(self):
        return 0


class ServerLock:
    """actionlib's ActionServer: one re-entrant lock, held around its callbacks and taken by
    every goal-handle method."""

    def __init__(self):
        self.lock = threading.RLock()


class FakeHandle:
    def __init__(self, server: ServerLock, goal_id: str):
        self.server, self.id, self.events = server, goal_id, []

    def _call(self, name, text=""):
        if not self.server.lock.acquire(timeout=5.0):
            raise AssertionError(f"{name}: actionlib lock never released (deadlock)")
        try:
            self.events.append((name, text))
        finally:
            self.server.lock.release()

    def set_canceled(self, _result=None, text=""):
        self._call("canceled", text)

    def set_succeeded(self, _result=None, text=""):
        self._call("succeeded", text)

    def set_aborted(self, _result=None, text=""):
        self._call("aborted", text)

    def publish_feedback(self, _feedback):
        self._call("feedback")

    def get_goal_id(self):
        class GoalId:
            id = self.id
        return GoalId()


def make_node() -> MoveBaseNode:
    node = MoveBaseNode(load_nav_config(CONFIG), FakeRospy(), tf_buffer=None)
    node._pubs = {k: FakePublisher() for k in ("cmd_vel", "global", "local", "plan", "tp_global",
                                               "tp_local", "goal", "global_footprint",
                                               "local_footprint")}
    node.lookup = lambda parent, child, stamp=None, wait=0.0: np.zeros(3)
    return node


def test_a_new_goal_during_a_controller_cycle_does_not_deadlock():
    """actionlib calls on_goal with its lock held; on_goal takes the node's lock. A cycle that
    sent feedback while holding the node's lock would wait for actionlib's: a deadlock."""
    node = make_node()
    server = node.server = ServerLock()
    first = FakeHandle(server, "g1")
    node._start_goal(np.array([2.0, 0.0, 0.0]), "map", first)
    errors = []

    def cycles():
        try:
            for _ in range(30):
                node.tick()
        except AssertionError as exc:
            errors.append(exc)

    def new_goals():
        try:
            for k in range(30):
                with server.lock:       # as ActionServer.internal_goal_callback
                    node._start_goal(np.array([1.0, 0.5 * (k % 3), 0.0]), "map",
                                     FakeHandle(server, f"n{k}"))
        except AssertionError as exc:
            errors.append(exc)

    threads = [threading.Thread(target=cycles), threading.Thread(target=new_goals)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(timeout=60.0)
    assert not any(thread.is_alive() for thread in threads), "deadlock"
    assert not errors, errors
    assert ("canceled", "") not in first.events
    # The first goal ends exactly once: preempted by a new goal or, when the cycle thread ran
    # first (no map here, so planning fails), aborted by move_base -- either order is legal.
    ends = [name for name, _ in first.events if name in ("canceled", "aborted", "succeeded")]
    assert len(ends) == 1 and ends[0] in ("canceled", "aborted"), first.events
    assert first.events[-1][0] == ends[0]


def test_cancel_of_the_current_goal_cancels_it_once():
    node = make_node()
    server = node.server = ServerLock()
    handle = FakeHandle(server, "g1")
    node._start_goal(np.array([2.0, 0.0, 0.0]), "map", handle)
    with server.lock:
        node.on_cancel(handle)
        node.on_cancel(handle)
    assert [e for e in handle.events if e[0] == "canceled"] == [("canceled", "")]
    assert node.handle is None and node.record is None


class FakeAck:
    def __init__(self, node):
        self.node, self.values, self.observations = node, [], []

    def publish(self, until):
        self.values.append(until)
        self.observations.append(self.node.navigator.local_costmap._scan)


def laser_scan(stamp: float, r: float = 1.0):
    import math

    import rospy
    from sensor_msgs.msg import LaserScan

    msg = LaserScan()
    msg.header.stamp = rospy.Time.from_sec(stamp)
    msg.header.frame_id = "base_laser_link"
    msg.angle_min, msg.angle_max = -math.pi / 2, math.pi / 2
    msg.angle_increment = math.pi / 90
    msg.range_min, msg.range_max = 0.1, 10.0
    msg.ranges = [r] * 91
    return msg


def test_every_scan_is_acked_with_its_stamp_once_it_is_in_the_costmap():
    """A lockstep stage_sim waits for ~scan_ack: it must come after the scan is the costmap's
    observation (applied at its next update), also when the scan could not be used (no
    transform: still acked, or the simulator would wait out its timeout)."""
    node = make_node()
    node._scan_ack = ack = FakeAck(node)
    node.on_scan(laser_scan(0.1))
    assert ack.values == [pytest.approx(0.1)]
    _sensor, points = ack.observations[0]               # stored before the ack
    np.testing.assert_allclose(np.hypot(*points.T), 1.0)
    node.lookup = lambda *a, **k: None                                 # tf missing
    node.on_scan(laser_scan(0.2))
    assert ack.values == [pytest.approx(0.1), pytest.approx(0.2)]
