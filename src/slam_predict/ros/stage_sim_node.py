"""``stage_sim``: a drop-in for stage_ros' ``stageros`` running :class:`slam_predict.sim.Simulator`.

Usage like stageros: ``rosrun slam_predict stage_sim path/to/world.world`` (or ``~world``).
It sets ``/use_sim_time`` true and, once per step of ``interval_sim`` of sim time, publishes
(all stamped with sim time; names relative, as stageros with one robot):

* ``/clock`` (rosgraph_msgs/Clock);
* ``odom`` (nav_msgs/Odometry): frame ``odom``, pose = odometry pose, twist = executed velocity
  (body frame). **Deviation:** ``child_frame_id`` is ``base_footprint`` (stageros leaves it
  empty, stage_ros #57; PRs #52/#59 set it as we do);
* ``base_pose_ground_truth`` (nav_msgs/Odometry): the true world pose; twist = finite difference
  of the world pose over the step (world frame). Its frame_id is ``~ground_truth_frame_id``,
  default ``odom`` as stageros (which mislabels the world frame that way);
* ``base_scan`` (sensor_msgs/LaserScan, frame ``base_laser_link``) when the laser is due;
* tf ``odom → base_footprint`` (odometry pose), ``base_footprint → base_link`` (identity),
  ``base_link → base_laser_link`` (laser mounting pose, z = ``~laser_z``).

Subscribes ``cmd_vel`` (geometry_msgs/Twist: linear.x, angular.z). Watchdog as stageros: when
no command arrived for ``~base_watchdog_timeout`` s of sim time (default 0.2; ≤ 0 disables)
the command becomes zero (with acceleration limits the robot then decelerates). Service
``reset_positions`` (std_srvs/Empty) puts the robot back at its start pose.

Pacing, ``~speedup``:

* ``1.0`` (default) real time; ``N`` N× faster than real time: step k is published at wall time
  start + k·interval_sim/N (the loop sleeps in wall time; it cannot use sim time, which it makes).
* ``0``: as fast as possible. With ``~lockstep`` false the steps run back to back, like headless
  Stage: subscribers that are slower drop messages. With ``~lockstep`` true (the default for
  speedup 0) the simulator runs in lockstep with its controller: after publishing a step it waits
  until a ``cmd_vel`` message arrives (controllers publish one per control cycle, reacting to the
  newest scan/tf), or until ``~lockstep_timeout`` wall seconds pass (default 0.05 s, so the
  simulation still advances when nothing is commanding the robot, e.g. before a goal is sent).
  Sim time therefore advances only as fast as the slowest link of the control loop allows.
  ``~lockstep_acks`` (list of ``[topic, lag]``, default empty) extends the lockstep to the
  whole graph: each topic carries std_msgs/Time "done with every input up to this sim time" (our
  slam_gmapping, move_base and explore publish ``~sim_ack``, see :mod:`slam_predict.ros.lockstep`);
  before the first step the simulator waits for every topic's first ack; before each step until
  every ack is ≥ the sim time − lag (s),
  or ≥ the newest scan's stamp when lag is ``scan`` (a scan consumer), for at most
  ``~lockstep_ack_timeout`` wall s (default 30; then it warns and steps on without waiting for
  that topic until it acks again: a dead node does not slow every step down). With acks the
  ``cmd_vel`` wait is not used when a periodic node acks (move_base); with scan consumers only
  (e.g. a plain cmd_vel publisher drives the robot) both waits apply.

Other params (read in :func:`main` only, by :mod:`slam_predict.ros.stage_sim_params`):
``~config`` YAML file with a ``sim:`` section (:class:`~slam_predict.sim.SimConfig`, e.g.
$(find slam_predict)/config/robot.yaml; default: the world file's robot with the default
SimConfig), ``~odom_model`` and ``~integrator`` (override the config), ``~seed`` (int; default:
fresh entropy, logged), ``~laser_z`` (m, default 0), ``~ground_truth_frame_id``,
``~wait_for_service`` (default empty: start at once; else do not step until that service
exists — the ROS path's orchestrator offers ``/orchestrator/ready`` once the run's nodes are
up). The odometry model and errors in use are set as ``~odom_error``.
"""
from __future__ import annotations

import logging
import sys
import threading
import time

import numpy as np

from slam_predict.geometry import wrap_angle
from slam_predict.ros.conversions import geometry as conv
from slam_predict.ros.conversions.sensor import scan_data, scan_to_ros
from slam_predict.ros.stage_sim_params import (
    NodeSettings,
    node_settings,
    sim_config,
    world_argument,
)
from slam_predict.sim import SimState, Simulator

LOG = logging.getLogger(__name__)


class StageSim:
    """Steps a Simulator and publishes its state as stageros does.

    Args:
        sim: the simulator (its World's start pose is the robot's).
        settings: pacing and watchdog.
        rospy_module: the ``rospy`` module (injected, so tests can run the class without a master).
    """

    def __init__(self, sim: Simulator, settings: NodeSettings, rospy_module):
        self.sim = sim
        self.settings = settings
        self.rospy = rospy_module
        self._lock = threading.Lock()
        self._command = (0.0, 0.0)
        self._last_command_t = -np.inf
        self._command_event = threading.Event()
        self._acks = {topic: -np.inf for topic, _ in settings.lockstep_acks}
        self._ack_cond = threading.Condition()
        self._late = set()
        self._last_scan_t = -np.inf
        # a controller that acks (a periodic node) replaces the cmd_vel wait
        self._wait_for_cmd_vel = not any(lag is not None for _, lag in settings.lockstep_acks)
        self._prev_true = sim.true_pose.copy()
        self._pubs = None
        self._stopping = False  # set by the shutdown hook

    # -- ROS plumbing ----------------------------------------------------------------------
    def start(self) -> None:
        """Advertise topics, subscribe cmd_vel, offer reset_positions (after init_node)."""
        import tf2_ros
        from geometry_msgs.msg import Twist
        from nav_msgs.msg import Odometry
        from rosgraph_msgs.msg import Clock
        from sensor_msgs.msg import LaserScan
        from std_srvs.srv import Empty

        rp = self.rospy
        self._pubs = {
            "clock": rp.Publisher("/clock", Clock, queue_size=10),
            "odom": rp.Publisher("odom", Odometry, queue_size=10),
            "truth": rp.Publisher("base_pose_ground_truth", Odometry, queue_size=10),
            "scan": rp.Publisher("base_scan", LaserScan, queue_size=10),
        }
        self._tf = tf2_ros.TransformBroadcaster()
        rp.Subscriber("cmd_vel", Twist, self.on_cmd_vel, queue_size=10)
        if self._acks:
            from std_msgs.msg import Time
            for topic in self._acks:
                rp.Subscriber(topic, Time, self.on_ack, callback_args=topic, queue_size=10)
        rp.Service("reset_positions", Empty, self.on_reset)
        rp.on_shutdown(self.wake)

    def wake(self) -> None:
        """Shutdown hook (rospy calls it before is_shutdown() turns true): end the lockstep
        waits now, as a shut-down node's acks never come, and step no more."""
        self._stopping = True
        self._command_event.set()
        with self._ack_cond:
            self._ack_cond.notify_all()

    def on_cmd_vel(self, msg) -> None:
        """cmd_vel callback: remember (linear.x, angular.z) and the sim time it arrived."""
        vx, _, w = conv.twist_from_ros(msg)
        with self._lock:
            self._command = (vx, w)
            self._last_command_t = self.sim.t
        self._command_event.set()

    def on_ack(self, msg, topic: str) -> None:
        """A lockstep ack: ``topic``'s node has processed its inputs up to ``msg.data``."""
        with self._ack_cond:
            self._acks[topic] = max(self._acks[topic], msg.data.to_sec())
            rejoined = topic in self._late
            self._late.discard(topic)
            self._ack_cond.notify_all()
        if rejoined:
            LOG.info("lockstep: %s acks again (%.1f s): waiting for it again", topic,
                     msg.data.to_sec())

    def stopped(self) -> bool:
        """True once shutdown began (hook called or rospy shut down)."""
        return self._stopping or self.rospy.is_shutdown()

    def wait_for_acks(self) -> bool:
        """Block until every ack topic is within its lag of the sim time (or the timeout);
        False when it timed out. A topic that timed out is logged and not waited for until it
        acks again (:meth:`on_ack`)."""
        due = {topic: self._last_scan_t if lag is None else self.sim.t - lag
               for topic, lag in self.settings.lockstep_acks}
        t = self.sim.t

        def behind():
            return [k for k, d in due.items() if k not in self._late and self._acks[k] < d - 1e-6]

        with self._ack_cond:
            done = self._ack_cond.wait_for(lambda: not behind() or self.stopped(),
                                           self.settings.lockstep_ack_timeout)
            late = set() if self.stopped() else set(behind())
            self._late |= late
        for topic in sorted(late):
            LOG.warning("lockstep: no ack on %s within %g s at sim time %.1f s: stepping on "
                        "without it until it acks again", topic,
                        self.settings.lockstep_ack_timeout, t)
        return bool(done)

    def wait_until_connected(self) -> None:
        """Before the first step: wait until every ack topic has delivered its (latched) first
        ack and, with scan consumers among them, ``base_scan`` has as many subscribers (no
        limit: the nodes may take long to start; the laggards are logged every timeout)."""
        scan_users = sum(lag is None for _, lag in self.settings.lockstep_acks)
        next_warning = time.monotonic() + self.settings.lockstep_ack_timeout
        while not self.rospy.is_shutdown():
            with self._ack_cond:
                missing = sorted(k for k, v in self._acks.items() if v == -np.inf)
            if not missing and self._pubs["scan"].get_num_connections() >= scan_users:
                return
            if time.monotonic() > next_warning:
                next_warning += self.settings.lockstep_ack_timeout
                LOG.warning("lockstep: still waiting for the first ack on %s (and %d scan "
                            "subscribers) before stepping", missing, scan_users)
            time.sleep(0.01)

    def on_reset(self, _request):
        """reset_positions service: robot back at the start pose, zero command."""
        from std_srvs.srv import EmptyResponse

        with self._lock:
            self.sim.reset()
            self._command = (0.0, 0.0)
            self._last_command_t = -np.inf
            self._prev_true = self.sim.true_pose.copy()
        return EmptyResponse()

    # -- stepping --------------------------------------------------------------------------
    def command(self) -> tuple:
        """The command for the next step, zero when the watchdog has expired."""
        timeout = self.settings.watchdog_timeout
        if timeout > 0 and self.sim.t - self._last_command_t >= timeout:
            return (0.0, 0.0)
        return self._command

    def step(self) -> SimState:
        """One simulator step, then publish everything for it."""
        with self._lock:
            self._command_event.clear()
            state = self.sim.step(*self.command())
            prev, self._prev_true = self._prev_true, state.true_pose.copy()
        self.publish(state, prev)
        return state

    def publish(self, state: SimState, prev_true: np.ndarray) -> None:
        """Clock, tf, odom, ground truth and (when taken) the scan of ``state``."""
        t, sim = state.t, self.sim
        self._pubs["clock"].publish(conv.clock_to_ros(t))
        laser_pose = sim.laser_pose
        self._tf.sendTransform([
            conv.transform_to_ros(state.odom_pose, t, "odom", "base_footprint"),
            conv.transform_to_ros((0.0, 0.0, 0.0), t, "base_footprint", "base_link"),
            conv.transform_to_ros(laser_pose, t, "base_link", "base_laser_link",
                                  z=self.settings.laser_z),
        ])
        self._pubs["odom"].publish(conv.odometry_to_ros(state.odom_pose, state.velocity, t,
                                                        "odom", "base_footprint"))
        world_velocity = self._finite_difference(prev_true, state.true_pose, sim.dt)
        self._pubs["truth"].publish(conv.odometry_to_ros(
            state.true_pose, world_velocity, t, self.settings.ground_truth_frame_id,
            "base_footprint"))
        if state.scan is not None:
            self._last_scan_t = t
            scan = scan_data(state.scan, sim.laser, t, "base_laser_link")
            self._pubs["scan"].publish(scan_to_ros(scan))

    @staticmethod
    def _finite_difference(prev: np.ndarray, now: np.ndarray, dt: float) -> tuple:
        """(vx, vy, ω) in the world frame over one step (stageros' ground-truth twist)."""
        dth = float(wrap_angle(now[2] - prev[2]))
        return ((now[0] - prev[0]) / dt, (now[1] - prev[1]) / dt, dth / dt)

    def run(self, max_steps: int | None = None) -> None:
        """Step until shutdown (or ``max_steps``), paced by ``speedup`` (module docstring)."""
        self._pubs["clock"].publish(conv.clock_to_ros(self.sim.t))
        if self.settings.speedup == 0 and self.settings.lockstep and self._acks:
            self.wait_until_connected()
        wall_start = time.monotonic()
        period = self.sim.dt / self.settings.speedup if self.settings.speedup > 0 else 0.0
        steps = 0
        while not self.stopped() and (max_steps is None or steps < max_steps):
            if period > 0:
                delay = wall_start + steps * period - time.monotonic()
                if delay > 0:
                    time.sleep(delay)
            if period == 0 and self.settings.lockstep and self._acks:
                self.wait_for_acks()
            self.step()
            steps += 1
            if period == 0 and self.settings.lockstep and self._wait_for_cmd_vel:
                self._command_event.wait(self.settings.lockstep_timeout)


def main(argv=None) -> int:
    """Node entry point: read ~params, load the world, step until shutdown."""
    import rospy

    from slam_predict.errors import InputError
    from slam_predict.world.load import load_plan

    rospy.set_param("/use_sim_time", True)  # as stageros: every node follows our /clock
    rospy.init_node("stage_sim", argv=argv)
    path = world_argument(rospy)
    if not path:
        rospy.logfatal("stage_sim: give a world file (stage_sim WORLD, or ~world)")
        return 2
    seed = rospy.get_param("~seed", None)
    if seed is None:
        seed = int(np.random.SeedSequence().entropy % (2 ** 63))
    try:
        world = load_plan(path)
        config = sim_config(rospy)
        sim = Simulator(world, config, np.random.default_rng(int(seed)))
        settings = node_settings(rospy)
    except InputError as exc:
        rospy.logfatal("stage_sim: %s", exc.one_line())
        return 2
    except ValueError as exc:
        rospy.logfatal("stage_sim: %s: %s", path, exc)
        return 2
    node = StageSim(sim, settings, rospy)
    node.start()
    rospy.loginfo("stage_sim: %s (%d x %d cells at %g m), seed %d, odometry %s, speedup %g",
                  world.name, world.shape[1], world.shape[0], world.resolution, int(seed),
                  sim.odom_error, node.settings.speedup)
    rospy.set_param("~odom_error", sim.odom_error)  # for run records (orchestrator)
    try:
        wait = rospy.get_param("~wait_for_service", "")  # e.g. the orchestrator's ~ready
        if wait:
            rospy.loginfo("stage_sim: waiting for %s before stepping", wait)
            rospy.wait_for_service(wait)
        node.run()
    except rospy.ROSInterruptException:
        pass
    return 0


if __name__ == "__main__":
    sys.exit(main())
