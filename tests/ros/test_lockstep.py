"""Lockstep ticks and acks (slam_predict.ros.lockstep) without a ROS master."""
from __future__ import annotations

import threading

import pytest

pytest.importorskip("std_msgs.msg", reason="ROS 1 python messages not installed")

from slam_predict.ros.lockstep import ACK_EPSILON, IDLE_FOREVER, SimTicker, next_tick  # noqa: E402


class FakeAck:
    def __init__(self):
        self.values = []

    def publish(self, until):
        self.values.append(until)


def test_next_tick_is_the_next_multiple_of_the_period():
    assert next_tick(0.0, 0.2) == pytest.approx(0.2)
    assert next_tick(0.2, 0.2) == pytest.approx(0.4)
    assert next_tick(0.30000000000000004, 0.1) == pytest.approx(0.4)   # float noise
    assert next_tick(0.35, 0.1) == pytest.approx(0.4)
    assert next_tick(12.9999999, 0.5) == pytest.approx(13.5)


def reference_ticks(clock, period):
    """Slow reference: the first clock time at or after each multiple of the period."""
    ticks, k = [], 1
    for t in clock:
        if t >= k * period - 1e-9:
            ticks.append(t)
            while k * period <= t + 1e-9:
                k += 1
    return ticks


def test_ticker_runs_once_per_period_at_sim_steps_and_acks_just_before_the_next():
    calls, ack = [], FakeAck()
    ticker = SimTicker(None, 0.2, calls.append, ack)
    clock = [round(0.1 * k, 10) for k in range(1, 21)] + [2.7, 2.8, 3.5]   # jumps at the end
    for t in clock:
        if ticker.due(t):
            ticker.run_once(t)
    assert calls == pytest.approx(reference_ticks(clock, 0.2))
    # an ack covers exactly the steps before the next tick: a lockstep simulator at t waits
    # (ack < t) iff a tick is due at t
    for t, until in zip(calls, ack.values, strict=False):
        assert until == pytest.approx(next_tick(t, 0.2) - ACK_EPSILON)


def test_stopped_ticker_acks_idle_forever_and_never_ticks_again():
    calls, ack = [], FakeAck()
    ticker = SimTicker(None, 0.1, calls.append, ack)
    ticker.run_once(0.1)
    ticker.stop()
    assert ack.values[-1] == IDLE_FOREVER


def test_failing_tick_still_acks():
    ack = FakeAck()

    def boom(_t):
        raise RuntimeError("tick failed")

    ticker = SimTicker(None, 0.1, boom, ack)
    with pytest.raises(RuntimeError):
        ticker.run_once(0.1)
    assert ack.values == [pytest.approx(0.2 - ACK_EPSILON)]


class FakeClockRospy:
    """rospy with sim time: the ticker's /clock subscription is captured, the test drives it."""

    def __init__(self):
        self.on_clock = None
        self.t = 0.0
        self.shutdown = False

    def get_param(self, name, default=None):
        return True if name == "/use_sim_time" else default

    def get_time(self):
        return self.t

    def is_shutdown(self):
        return self.shutdown

    def Subscriber(self, _topic, _type, callback, queue_size=None):  # noqa: N802 (rospy API)
        self.on_clock = callback


class ThreadAck:
    """An AckPublisher double a simulator thread can wait on."""

    def __init__(self):
        self.cond = threading.Condition()
        self.values = []

    def publish(self, until):
        with self.cond:
            self.values.append(until)
            self.cond.notify_all()

    def wait_past(self, t, timeout=5.0):
        with self.cond:
            return self.cond.wait_for(lambda: self.values and self.values[-1] >= t - 1e-9,
                                      timeout)


def test_ticker_thread_in_lockstep_with_a_simulator_and_stopping_from_its_own_tick():
    """The simulator publishes /clock, then waits for an ack covering it before the next step
    (stage_sim with lag 0). The ticker thread must tick exactly at the period's multiples, never
    leave the simulator waiting (a lost ack = a deadlock of the graph), and a tick that stops
    the ticker (the explorer's end) must ack "idle forever" without hanging the thread."""
    import rospy
    from rosgraph_msgs.msg import Clock

    fake, ack, calls = FakeClockRospy(), ThreadAck(), []
    ticker = SimTicker(fake, 0.2, None, ack)

    def tick(now):
        calls.append(now)
        if now >= 1.0 - 1e-9:
            ticker.stop()

    ticker.callback = tick
    ticker.start()
    assert ack.values == [pytest.approx(0.2 - ACK_EPSILON)]   # ready before the first step
    try:
        for k in range(1, 21):
            fake.t = round(0.1 * k, 10)
            fake.on_clock(Clock(rospy.Time.from_sec(fake.t)))
            assert ack.wait_past(fake.t), f"no ack covering t = {fake.t} (lockstep deadlock)"
    finally:
        fake.shutdown = True
    assert calls == pytest.approx([0.2, 0.4, 0.6, 0.8, 1.0])
    assert ack.values[-1] == IDLE_FOREVER
