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

Other params (read in :func:`main` only): ``~config`` YAML file with a ``sim:`` section
(:class:`~slam_predict.sim.SimConfig`, e.g. $(find slam_predict)/config/robot.yaml; default: the
world file's robot with the default SimConfig), ``~odom_model`` and ``~integrator`` (override the
config), ``~seed`` (int; default: fresh entropy, logged), ``~laser_z`` (m, default 0),
``~ground_truth_frame_id``, ``~wait_for_service`` (default empty: start at once; else do not
step until that service exists — the ROS path's orchestrator offers ``/orchestrator/ready`` once
the run's nodes are up). The odometry model and errors in use are set as ``~odom_error``.
"""
from __future__ import annotations

import logging
import sys
import threading
import time
from dataclasses import dataclass
from typing import Optional

import numpy as np

from slam_predict.geometry import wrap_angle
from slam_predict.ros.conversions import geometry as conv
from slam_predict.ros.conversions.sensor import scan_data, scan_to_ros
from slam_predict.sim import SimState, Simulator

LOG = logging.getLogger(__name__)


@dataclass
class NodeSettings:
    """Node behaviour (the node's private params); see the module docstring."""

    watchdog_timeout: float = 0.2
    speedup: float = 1.0
    lockstep: bool = True
    lockstep_timeout: float = 0.05
    laser_z: float = 0.0
    ground_truth_frame_id: str = "odom"


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
        self._prev_true = sim.true_pose.copy()
        self._pubs = None

    # -- ROS plumbing ----------------------------------------------------------------------
    def start(self) -> None:
        """Advertise topics, subscribe cmd_vel, offer reset_positions (after init_node)."""
        import tf2_ros
        from nav_msgs.msg import Odometry
        from rosgraph_msgs.msg import Clock
        from sensor_msgs.msg import LaserScan
        from geometry_msgs.msg import Twist
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
        rp.Service("reset_positions", Empty, self.on_reset)

    def on_cmd_vel(self, msg) -> None:
        """cmd_vel callback: remember (linear.x, angular.z) and the sim time it arrived."""
        vx, _, w = conv.twist_from_ros(msg)
        with self._lock:
            self._command = (vx, w)
            self._last_command_t = self.sim.t
        self._command_event.set()

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
            scan = scan_data(state.scan, sim.laser, t, "base_laser_link")
            self._pubs["scan"].publish(scan_to_ros(scan))

    @staticmethod
    def _finite_difference(prev: np.ndarray, now: np.ndarray, dt: float) -> tuple:
        """(vx, vy, ω) in the world frame over one step (stageros' ground-truth twist)."""
        dth = float(wrap_angle(now[2] - prev[2]))
        return ((now[0] - prev[0]) / dt, (now[1] - prev[1]) / dt, dth / dt)

    def run(self, max_steps: Optional[int] = None) -> None:
        """Step until shutdown (or ``max_steps``), paced by ``speedup`` (module docstring)."""
        self._pubs["clock"].publish(conv.clock_to_ros(self.sim.t))
        wall_start = time.monotonic()
        period = self.sim.dt / self.settings.speedup if self.settings.speedup > 0 else 0.0
        steps = 0
        while not self.rospy.is_shutdown() and (max_steps is None or steps < max_steps):
            if period > 0:
                delay = wall_start + steps * period - time.monotonic()
                if delay > 0:
                    time.sleep(delay)
            self.step()
            steps += 1
            if period == 0 and self.settings.lockstep:
                self._command_event.wait(self.settings.lockstep_timeout)


def _world_argument(rospy_module) -> str:
    """The world file: first non-flag command-line argument (as stageros), else ``~world``."""
    args = [a for a in rospy_module.myargv(sys.argv)[1:] if not a.startswith("-")]
    return args[0] if args else rospy_module.get_param("~world", "")


def _sim_config(rospy_module):
    """SimConfig from ``~config`` (section ``sim``), then ``~odom_model``/``~integrator``."""
    import dataclasses

    from slam_predict.config import load_config
    from slam_predict.errors import InputError
    from slam_predict.sim import SimConfig

    path = rospy_module.get_param("~config", "")
    config = load_config(SimConfig, path, "sim") if path else SimConfig()
    model = rospy_module.get_param("~odom_model", "")
    integrator = rospy_module.get_param("~integrator", "")
    try:
        if model:
            config = dataclasses.replace(config, odom=dataclasses.replace(config.odom,
                                                                          model=model))
        if integrator:
            config = dataclasses.replace(config, integrator=integrator)
    except ValueError as exc:
        raise InputError(str(exc), path or None) from None
    return config


def _settings(rospy_module) -> NodeSettings:
    get = rospy_module.get_param
    speedup = float(get("~speedup", 1.0))
    return NodeSettings(
        watchdog_timeout=float(get("~base_watchdog_timeout", 0.2)),
        speedup=max(speedup, 0.0),
        lockstep=bool(get("~lockstep", True)),
        lockstep_timeout=float(get("~lockstep_timeout", 0.05)),
        laser_z=float(get("~laser_z", 0.0)),
        ground_truth_frame_id=str(get("~ground_truth_frame_id", "odom")))


def main(argv=None) -> int:
    """Node entry point: read ~params, load the world, step until shutdown."""
    import rospy

    from slam_predict.errors import InputError
    from slam_predict.world.load import load_plan

    rospy.set_param("/use_sim_time", True)  # as stageros: every node follows our /clock
    rospy.init_node("stage_sim", argv=argv)
    path = _world_argument(rospy)
    if not path:
        rospy.logfatal("stage_sim: give a world file (stage_sim WORLD, or ~world)")
        return 2
    seed = rospy.get_param("~seed", None)
    if seed is None:
        seed = int(np.random.SeedSequence().entropy % (2 ** 63))
    try:
        world = load_plan(path)
        config = _sim_config(rospy)
        sim = Simulator(world, config, np.random.default_rng(int(seed)))
    except InputError as exc:
        rospy.logfatal("stage_sim: %s", exc.one_line())
        return 2
    except ValueError as exc:
        rospy.logfatal("stage_sim: %s: %s", path, exc)
        return 2
    node = StageSim(sim, _settings(rospy), rospy)
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
