"""Lockstep acks: how a node tells a lockstep ``stage_sim`` that it has done its work.

A node publishes std_msgs/Time on ``~sim_ack`` (latched) = "done with everything due up to this
sim time". A scan consumer acks each scan's stamp. A periodic node is stepped by
:class:`SimTicker` at the multiples of its period P of sim time; once the tick due at τ has run it
acks τ + P − :data:`ACK_EPSILON` (nothing to do before τ + P), so the simulator steps up to the
next tick time and waits there until that tick has run (``stage_sim`` ``~lockstep_acks``). A node
that will never tick again acks :data:`IDLE_FOREVER`.
"""
from __future__ import annotations

import logging
import math
import threading
from collections.abc import Callable

ACK_EPSILON = 1e-3        # s: an ack stops this short of the next tick (sim steps are >= 10 ms)
IDLE_FOREVER = 2.0 ** 31  # s: "nothing more to do" (the largest std_msgs/Time second)
TIME_TOLERANCE = 1e-6     # s: float noise when comparing sim times
LOG = logging.getLogger(__name__)


def next_tick(now: float, period: float) -> float:
    """The first multiple of ``period`` strictly after ``now`` (s)."""
    return (math.floor(now / period + TIME_TOLERANCE) + 1) * period


def warm(*modules: str) -> None:
    """Load (compile at worst) the numba kernels of ``modules`` (each has ``warmup()``) before a
    node offers its first ack, so a lockstep simulator does not wait out their loading on the
    first steps."""
    import importlib

    for name in modules:
        importlib.import_module(name).warmup()


class AckPublisher:
    """``~sim_ack`` of one node (created after ``rospy.init_node``; latched, so a simulator that
    subscribes late still gets the newest ack)."""

    def __init__(self, rospy_module, topic: str = "~sim_ack"):
        from std_msgs.msg import Time

        self.rospy = rospy_module
        self._time = Time
        self.publisher = rospy_module.Publisher(topic, Time, queue_size=10, latch=True)
        self.last: float | None = None

    def publish(self, until: float) -> None:
        """Ack every input up to ``until`` (sim s)."""
        self.last = until
        self.publisher.publish(self._time(self.rospy.Time.from_sec(until)))


class SimTicker:
    """Calls ``callback(now)`` at every multiple of ``period`` s of ROS time, in its own thread,
    and acks after each call (:class:`AckPublisher`).

    With sim time it follows ``/clock`` directly (rospy.Timer's schedule starts at the first
    non-zero clock and drifts from the multiples of its period, which a lockstep simulator cannot
    predict); a tick whose time was skipped (the clock jumped) runs once, at the newest time. With
    wall time it falls back to ``rospy.Timer``.
    """

    def __init__(self, rospy_module, period: float, callback: Callable[[float], None],
                 ack: AckPublisher | None = None):
        self.rospy = rospy_module
        self.period = float(period)
        self.callback = callback
        self.ack = ack
        self.next = self.period
        self._now = 0.0
        self._cond = threading.Condition()
        self._stopped = False
        self._timer = None

    # ------------------------------------------------------------------------------ pure logic
    def due(self, now: float) -> bool:
        """True when the tick scheduled at ``self.next`` is due at ROS time ``now``."""
        return now >= self.next - TIME_TOLERANCE

    def run_once(self, now: float) -> None:
        """Run the due tick at ``now``, schedule the next one and ack up to just before it."""
        try:
            self.callback(now)
        finally:
            self.next = next_tick(now, self.period)
            if self.ack is not None and not self._stopped:
                self.ack.publish(self.next - ACK_EPSILON)

    def stop(self) -> None:
        """No more ticks; ack "idle forever"."""
        self._stopped = True
        if self.ack is not None:
            self.ack.publish(IDLE_FOREVER)
        if self._timer is not None:
            self._timer.shutdown()
        with self._cond:
            self._cond.notify_all()

    # ------------------------------------------------------------------------------ ROS wiring
    def start(self) -> None:
        """Begin ticking (after init_node)."""
        rp = self.rospy
        if not rp.get_param("/use_sim_time", False):
            self._timer = rp.Timer(rp.Duration(self.period),
                                   lambda _e: self.callback(rp.get_time()))
            return
        from rosgraph_msgs.msg import Clock

        now = rp.get_time()
        self.next = next_tick(now, self.period) if now > 0 else self.period
        if self.ack is not None:
            self.ack.publish(self.next - ACK_EPSILON)
        rp.Subscriber("/clock", Clock, self._on_clock, queue_size=10)
        threading.Thread(target=self._loop, name="sim_ticker", daemon=True).start()

    def _on_clock(self, msg) -> None:
        with self._cond:
            self._now = max(self._now, msg.clock.to_sec())
            self._cond.notify_all()

    def _loop(self) -> None:
        while not self.rospy.is_shutdown() and not self._stopped:
            with self._cond:
                self._cond.wait_for(lambda: self.due(self._now) or self._stopped, timeout=0.5)
                now = self._now
            if self._stopped or not self.due(now):
                continue
            try:
                self.run_once(now)
            except Exception:  # a failing tick must not stop the node's clock
                LOG.exception("tick at %.3f s failed", now)
