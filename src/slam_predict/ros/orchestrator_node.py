"""``orchestrator``: records one exploration run of the ROS graph and applies the stop rule.

Subscribes ``/clock`` (sim time; on a real robot a 10 Hz timer drives it instead), the SLAM
``map`` (nav_msgs/OccupancyGrid), the ground-truth source (:mod:`slam_predict.ros.ground_truth`:
``base_pose_ground_truth`` by default, or a mocap PoseStamped / Odometry topic / tf frame) and
``/rosout_agg`` and ``/rosout`` (explore_lite says "Exploration stopped" when no frontier is
left); looks up tf map→base_link and odom→base_link at every sample time. The logic is
:class:`~slam_predict.ros.orchestrator.RunMonitor`; at the end the run record is written
atomically to ``~out`` (:mod:`slam_predict.ros.run_record`, the in-process format), the run's
nodes are shut down in order and the node exits, which ends the run's launch.

Params (read in :func:`main` only, :func:`~slam_predict.ros.orchestrator_config.read_setup`):
``~out`` (run folder, required), ``~world_file`` (Stage world or any plan; empty on a real
robot), ``~world_name`` (default: file stem), ``~run_index``, ``~seed``, ``~settings``
(collect.yaml: stop rule, metric, component configs), ``~config`` (orchestrator.yaml: ground
truth, frames, sampling), overrides ``~max_sim_time``, ``~max_wall_time``,
``~snapshot_interval`` (s; ≤ 0 keeps the settings'), ``~ground_truth_source``,
``~ground_truth_topic``, ``~ground_truth_frame``, ``~ground_truth_fixed_frame`` (empty keeps the
config's), ``~free_area_m2`` (without a world file), ``~odometry_model``, ``~sim_node`` (where
the simulator reports its odometry error, default ``/stage_sim``), ``~wait_for_nodes`` (nodes
that must be registered before ``~ready`` is offered) and ``~sim``, ``~slam``, ``~nav``,
``~explore`` (the node choices, recorded in run.json), ``~shutdown_nodes`` (the run's nodes,
shut down in this order once the record is written: simulator first, see
:mod:`slam_predict.ros.node_shutdown`; empty: none) and ``~shutdown_timeout`` (wall s each).

Services: ``~ready`` (std_srvs/Empty, offered once the run's nodes are up: stage_sim waits for
it before stepping), ``~stop`` (std_srvs/Trigger: end the run now and write the record).
"""
from __future__ import annotations

import dataclasses
import logging
import threading
import time

import numpy as np

from slam_predict.geometry import compose
from slam_predict.ros.ground_truth import GroundTruthSource
from slam_predict.ros.orchestrator import RunMonitor, Sample
from slam_predict.ros.orchestrator_config import OrchestratorConfig, RunSetup, read_setup

LOG = logging.getLogger(__name__)
SHUTDOWN_TIMEOUT_S = 40.0  # wall s a node gets to exit (stage_sim's lockstep ack wait is 30 s)


class OrchestratorNode:
    """ROS plumbing around a :class:`RunMonitor` (see the module docstring).

    Args:
        monitor: the run's logic; config: frames, topics and timeouts; ground_truth: the source;
        rospy_module, tf_buffer: injected (tests pass fakes).
    """

    def __init__(self, monitor: RunMonitor, config: OrchestratorConfig,
                 ground_truth: GroundTruthSource, rospy_module, tf_buffer):
        self.monitor = monitor
        self.config = config
        self.ground_truth = ground_truth
        self.rospy = rospy_module
        self.tf = tf_buffer
        self.lock = threading.Lock()
        self.maps = 0

    # -- ROS plumbing ----------------------------------------------------------------------
    def start(self, use_sim_time: bool) -> None:
        """Subscribe clock (or start the timer), map, /rosout_agg and /rosout."""
        from rosgraph_msgs.msg import Clock, Log

        from slam_predict.ros.conversions.slam import NumpyOccupancyGrid

        rp = self.rospy
        if use_sim_time:
            rp.Subscriber("/clock", Clock, self.on_clock, queue_size=100)
        else:
            period = self.config.sampling.sample_period_s
            rp.Timer(rp.Duration(period), lambda _event: self.tick(rp.get_time()))
        rp.Subscriber(self.config.map_topic, NumpyOccupancyGrid, self.on_map, queue_size=1,
                      buff_size=2 ** 26)
        # /rosout_agg needs the rosout node, which rostest does not start: read /rosout as well
        # (the explorer's end is kept once: the duplicate is ignored)
        for topic in ("/rosout_agg", "/rosout"):
            rp.Subscriber(topic, Log, self.on_log, queue_size=100)

    def on_clock(self, msg) -> None:
        from slam_predict.ros.conversions.geometry import clock_from_ros
        self.tick(clock_from_ros(msg))

    def tick(self, t: float) -> None:
        """Time advanced: sampling, snapshots and stop rules, then resolve queued samples."""
        with self.lock:
            self.monitor.tick(t)
            self.monitor.resolve(self.lookup)

    def on_map(self, msg) -> None:
        from slam_predict.ros.conversions.slam import grid_from_ros
        grid = grid_from_ros(msg)
        with self.lock:
            self.monitor.set_map(grid)
            self.maps += 1

    def on_log(self, msg) -> None:
        """explore_lite logs "Exploration stopped." when it gives up (no frontier left)."""
        explorer = self.config.explorer
        if msg.name == explorer.node and explorer.stopped_text in msg.msg:
            with self.lock:
                now = self.monitor.now if self.monitor.now is not None else 0.0
                self.monitor.set_explorer_end(now, msg.msg.strip())

    # -- poses -----------------------------------------------------------------------------
    def tf_pose(self, parent: str, child: str, t: float | None) -> np.ndarray | None:
        """Pose of ``child`` in ``parent`` at ``t`` s (None = latest), or None if not available."""
        return None if (found := self._tf_lookup(parent, child, t)) is None else found[1]

    def _tf_lookup(self, parent: str, child: str, t: float | None):
        from slam_predict.ros.conversions.geometry import (
            time_from_ros,
            time_to_ros,
            transform_from_ros,
        )
        stamp = self.rospy.Time(0) if t is None else time_to_ros(t)
        try:
            if not self.tf.can_transform(parent, child, stamp):
                return None
            msg = self.tf.lookup_transform(parent, child, stamp)
        except Exception as exc:  # noqa: BLE001 - tf2 raises several kinds; all mean "not now"
            LOG.debug("tf %s -> %s at %s: %s", parent, child, t, exc)
            return None
        return time_from_ros(msg.header.stamp), transform_from_ros(msg).pose

    def map_to_odom(self, t: float, now: float) -> np.ndarray | None:
        """tf map→odom at ``t``; the latest one once ``map_odom_hold_s`` has passed without a
        newer one (slam_gmapping keeps map→odom constant between processed scans)."""
        frames = self.config.frames
        pose = self.tf_pose(frames.map, frames.odom, t)
        if pose is not None:
            return pose
        latest = self._tf_lookup(frames.map, frames.odom, None)
        if latest is None:
            return None
        stamp, pose = latest
        if stamp >= t or now - t >= self.config.map_odom_hold_s:
            return pose
        return None

    def lookup(self, t: float, now: float) -> Sample | None:
        """The sample at ``t``: ground truth, SLAM pose (map→odom ∘ odom→base), odometry pose."""
        gt = self.ground_truth.at(t)
        if gt is None:
            return None
        frames = self.config.frames
        odom = self.tf_pose(frames.odom, frames.base, t)
        if odom is None:
            return None
        map_T_odom = self.map_to_odom(t, now)
        if map_T_odom is None:
            return None
        return Sample(t, gt, compose(map_T_odom, odom), odom)

    # -- start of run ----------------------------------------------------------------------
    def wait_for_nodes(self, names, registered, poll_s: float = 0.2) -> list:
        """Wait (wall, up to ``startup_timeout_s``) until every node of ``names`` is registered
        (``registered()`` → set of node names); returns the ones still missing."""
        deadline = time.monotonic() + self.config.startup_timeout_s
        while True:
            missing = sorted(set(names) - registered())
            if not missing or time.monotonic() >= deadline or self.rospy.is_shutdown():
                return missing
            time.sleep(poll_s)

    def offer_ready(self) -> None:
        """Advertise ``~ready`` (std_srvs/Empty): stage_sim starts stepping when it exists; and
        ``~stop`` (std_srvs/Trigger): end the run now and write its record."""
        from std_srvs.srv import Empty, EmptyResponse, Trigger
        self.rospy.Service("~ready", Empty, lambda _request: EmptyResponse())
        self.rospy.Service("~stop", Trigger, self.on_stop)

    def on_stop(self, _request):
        """``~stop`` service: the run ends with reason ``stop_requested``."""
        from std_srvs.srv import TriggerResponse
        with self.lock:
            self.monitor.request_stop()
            return TriggerResponse(success=True, message=f"stopping: {self.monitor.reason}")

    # -- end of run ------------------------------------------------------------------------
    def wait_until_done(self, poll_s: float = 0.05) -> bool:
        """Block until the stop rule ends the run (True) or ROS shuts down (False)."""
        while not self.rospy.is_shutdown():
            with self.lock:
                if self.monitor.done:
                    return True
            time.sleep(poll_s)
        return False

    def drain(self, poll_s: float = 0.05) -> int:
        """Resolve the samples still queued (up to ``finish_timeout_s`` wall); returns drops."""
        deadline = time.monotonic() + self.config.finish_timeout_s
        while time.monotonic() < deadline and not self.rospy.is_shutdown():
            with self.lock:
                self.monitor.resolve(self.lookup)
                if not self.monitor.pending:
                    return 0
            time.sleep(poll_s)
        with self.lock:
            return self.monitor.drop_pending()


class _Interrupted(Exception):
    """ROS shut down before the stop rule ended the run: no record is written."""


def run(setup: RunSetup, rospy_module, tf_buffer, use_sim_time: bool) -> dict:
    """Record one run into ``setup.out`` (atomically); returns run.json's content."""
    from slam_predict.atomic import atomic_dir
    from slam_predict.collect import record as rec
    from slam_predict.ros.run_record import build_record, write_record

    wall_start = time.monotonic()
    t0 = 0.0 if use_sim_time else rospy_module.get_time()
    from slam_predict import slam

    stop, choice = setup.stop, setup.settings.slam
    extent = slam.backend_class(choice.type).extent_of(choice.params)
    with atomic_dir(setup.out) as folder:
        monitor = RunMonitor(stop, stop.interval_for(setup.free_area_m2 or float("inf")),
                             extent, setup.config.sampling, t0,
                             on_snapshot=lambda i, image: rec.write_snapshot(folder, i, image))
        gt = GroundTruthSource(setup.config.ground_truth, rospy_module)
        node = OrchestratorNode(monitor, setup.config, gt, rospy_module, tf_buffer)
        gt.tf_pose = node.tf_pose
        node.start(use_sim_time)
        missing = node.wait_for_nodes(setup.wait_for_nodes, _registered_nodes)
        if missing:
            raise RuntimeError(f"nodes not up after {setup.config.startup_timeout_s:.0f} s: "
                               + ", ".join(missing))
        node.offer_ready()
        ready = time.monotonic()
        with node.lock:
            monitor.wall_start = monitor.wall_clock()  # the wall-clock limit counts from here
        if not node.wait_until_done():
            raise _Interrupted()
        stopped = time.monotonic()
        node.drain()
        drained = time.monotonic()
        odometry = rospy_module.get_param(setup.sim_node + "/odom_error", None)
        info = dataclasses.replace(setup.info, odometry_error=odometry)
        if isinstance(odometry, dict) and odometry.get("model"):
            info.odometry_model = str(odometry["model"])  # what the simulator really used
        info.ros.update({"ground_truth": gt.describe(), "maps_received": node.maps,
                         "ground_truth_messages": gt.messages})
        timing = {"startup_s": ready - wall_start, "run_s": stopped - ready,
                  "drain_s": drained - stopped}
        record = build_record(info, setup.settings, monitor, setup.world, setup.free_area_m2,
                              stopped - ready, timing)
        write_record(folder, record, monitor, setup.settings)
    return record


def _registered_nodes() -> set:
    """Names of the nodes the master knows (publishers, subscribers, service providers)."""
    import rosgraph
    state = rosgraph.Master("/orchestrator").getSystemState()
    return {node for kind in state for _topic, nodes in kind for node in nodes}


def main(argv=None) -> int:
    """Node entry point: read ~params, record the run, write its record, exit."""
    import rospy
    import tf2_ros

    from slam_predict.errors import InputError
    from slam_predict.ros.rosout import forward_logging

    rospy.init_node("orchestrator", argv=argv)
    forward_logging(rospy)
    try:
        setup = read_setup(rospy)
    except InputError as exc:
        rospy.logfatal("orchestrator: %s", exc.one_line())
        return 2
    use_sim_time = bool(rospy.get_param("/use_sim_time", False))
    cache = max(30.0, 3 * setup.config.sampling.max_sample_delay_s)
    tf_buffer = tf2_ros.Buffer(cache_time=rospy.Duration(cache))
    listener = tf2_ros.TransformListener(tf_buffer)  # noqa: F841 - keeps the subscription
    try:
        record = run(setup, rospy, tf_buffer, use_sim_time)
    except _Interrupted:
        rospy.logwarn("orchestrator: shut down before the run ended; no record written")
        return 1
    except (RuntimeError, ValueError) as exc:  # a node missing; the robot never moved...
        rospy.logerr("orchestrator: no record written for %s: %s", setup.out, exc)
        end_run(rospy)
        return 1
    rospy.loginfo("orchestrator: %s run %d: %s after %.1f s (%.1f s wall), %d poses -> %s",
                  record["world"], record["run_index"], record["stop_reason"],
                  record["sim_duration_s"], record["wall_time_s"], record["ros"]["samples"],
                  setup.out)
    end_run(rospy)
    return 0


def end_run(rospy_module) -> None:
    """Shut the run's nodes (``~shutdown_nodes``, in that order: simulator first) down before
    this node exits, so its launch ends without killing anything."""
    from slam_predict.ros.node_shutdown import end_run_graph

    names = str(rospy_module.get_param("~shutdown_nodes", "")).split()
    timeout = float(rospy_module.get_param("~shutdown_timeout", SHUTDOWN_TIMEOUT_S))
    if names:
        stuck = end_run_graph(names, timeout, caller=rospy_module.get_name())
        if stuck:
            rospy_module.logwarn("orchestrator: still running after %.0f s: %s", timeout,
                                 " ".join(stuck))
