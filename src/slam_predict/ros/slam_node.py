"""``slam_gmapping``: our SLAM node, a drop-in for the ROS slam_gmapping node, over any
registered back-end of :mod:`slam_predict.slam` (``~type``, default ``gmapping``:
:mod:`slam_predict.slam.gmapping`).

Topics, frames, parameters and timing as slam_gmapping (ros_interfaces.md §2.1–2.2), whatever
the back-end:

* subscribes ``scan`` (sensor_msgs/LaserScan, queue 5); the odometry is tf ``odom_frame →
  base_frame`` at the scan's stamp, the laser's mounting tf ``base_frame → laser frame`` is read
  once at the first scan (the laser must be planar, upright or upside down);
* publishes ``map`` (nav_msgs/OccupancyGrid, latched) and ``map_metadata`` (latched) after the
  first processed scan and then whenever a processed scan is more than the back-end's
  ``map_update_interval`` s newer than the last map (a back-end with a ``map_thread``, Karto as
  slam_toolbox, at any scan that much newer, processed or not); ``~entropy``
  (std_msgs/Float64, latched, only when > 0); ``~sim_ack`` (std_msgs/Time, latched): each
  scan's stamp once it is handled (0 at start; stage_sim's lockstep,
  :mod:`slam_predict.ros.lockstep`);
* broadcasts tf ``map_frame → odom_frame`` every ``transform_publish_period`` s (0 disables),
  stamped now + ``tf_delay``; it changes only when a scan is processed (a broadcast whose stamp
  would repeat the previous one is skipped: with sim time, slam_gmapping floods tf2 with
  TF_REPEATED_DATA warnings there);
* service ``dynamic_map`` (nav_msgs/GetMap).

Parameters (private namespace): ``~type`` (the back-end, a name of
:func:`slam_predict.slam.available`; an unknown one is a fatal one-line error listing them), the
node's own :class:`~slam_predict.slam.SlamNodeParams` (slam_gmapping's names), every field of the
back-end's parameter class (for gmapping
:class:`~slam_predict.slam.gmapping.params.GMappingParams`) and ``~seed`` (int; default: fresh
entropy, logged). Back-ends registered outside slam_predict are loaded from
``$SLAM_PREDICT_EXTRA_BACKENDS`` (a launch file sets it with ``<env>``; docs/architecture.md
"Adding a SLAM back-end").

The same node serves Karto under slam_toolbox's executable names (:data:`TOOLBOX_NODES`):
``sync_slam_toolbox_node`` (back-end ``karto``, ``scan_gate: sync``: slam_toolbox's
shouldProcessScan) and ``async_slam_toolbox_node`` (``scan_gate: async``: scans that arrive while
the mapper is busy wait or are dropped, :mod:`slam_predict.slam.karto.realtime`; ``none`` is
kept). Their private parameters are slam_toolbox's names (config/karto.yaml); a ``~type`` other
than ``karto`` is a fatal one-line error, a ``~scan_gate`` the executable does not run is
replaced by its own (logged). Readings below ``range_min`` become ``range_max`` (slam_gmapping's
rule); NaN readings are treated the same way (slam_gmapping would register them as garbage).
"""
from __future__ import annotations

import dataclasses
import logging
import math
import threading
import time

import numpy as np

from slam_predict.slam import SlamChoice, SlamNodeParams
from slam_predict.slam.laser import laser_geometry, prepare_ranges, quaternion_matrix

LOG = logging.getLogger(__name__)
SCAN_QUEUE = 5
# executable -> (default back-end, scan gates it runs: the first is its own); slam_gmapping runs
# any back-end as configured
TOOLBOX_NODES = {"sync_slam_toolbox_node": ("karto", ("sync",)),
                 "async_slam_toolbox_node": ("karto", ("async", "none"))}
TF_WAIT = 1.0  # s of wall time to wait for the odometry tf of a scan


class SlamNode:
    """slam_gmapping's behaviour around any SLAM back-end.

    Args:
        slam: the back-end's name and parameters.
        node: the node's own parameters (frames, throttling, tf period).
        seed: seed of the back-end's random generator.
        rospy_module: the ``rospy`` module (injected so tests can use a fake).
        tf_buffer: a ``tf2_ros.Buffer`` (``lookup_transform``, ``can_transform``).
        tf_broadcaster: a ``tf2_ros.TransformBroadcaster``.
    """

    def __init__(self, slam: SlamChoice, node: SlamNodeParams, seed: int, rospy_module, tf_buffer,
                 tf_broadcaster):
        self.choice = slam
        self.params = node
        self.seed = seed
        self.rospy = rospy_module
        self.tf_buffer = tf_buffer
        self.tf_broadcaster = tf_broadcaster
        self.slam = None
        self.reverse = False
        self.laser_count = 0
        self.last_map_update: float | None = None
        self.map_msg = None
        self.map_to_odom = np.zeros(3)
        self._lock = threading.Lock()
        self._map_lock = threading.Lock()
        self._pubs = {}
        self._last_tf_stamp: float | None = None

    # ------------------------------------------------------------------ wiring
    def start(self) -> None:
        """Advertise, subscribe, and start the map → odom broadcaster thread."""
        from nav_msgs.msg import MapMetaData
        from nav_msgs.srv import GetMap
        from sensor_msgs.msg import LaserScan
        from std_msgs.msg import Float64, Time

        from slam_predict.ros.conversions.slam import NumpyOccupancyGrid

        rp = self.rospy
        self._pubs["entropy"] = rp.Publisher("~entropy", Float64, queue_size=1, latch=True)
        self._pubs["map"] = rp.Publisher("map", NumpyOccupancyGrid, queue_size=1, latch=True)
        self._pubs["map_metadata"] = rp.Publisher("map_metadata", MapMetaData, queue_size=1,
                                                  latch=True)
        rp.Service("dynamic_map", GetMap, self.on_get_map)
        rp.Subscriber("scan", LaserScan, self.on_scan, queue_size=SCAN_QUEUE)
        self._pubs["ack"] = rp.Publisher("~sim_ack", Time, queue_size=10, latch=True)
        self._pubs["ack"].publish(Time())   # ready: no scan pending
        if self.params.transform_publish_period > 0:
            threading.Thread(target=self._publish_loop, daemon=True).start()

    def _publish_loop(self) -> None:
        rate = self.rospy.Rate(1.0 / self.params.transform_publish_period)
        while not self.rospy.is_shutdown():
            self.publish_transform()
            try:
                rate.sleep()
            except Exception:  # ROSInterruptException / time moved backwards at shutdown
                if self.rospy.is_shutdown():
                    return

    # ------------------------------------------------------------------ callbacks
    def on_scan(self, msg) -> None:
        """laserCallback, then ``~sim_ack`` = the scan's stamp (stage_sim's lockstep waits for
        it)."""
        try:
            self._process_scan(msg)
        finally:
            if "ack" in self._pubs:
                from std_msgs.msg import Time
                self._pubs["ack"].publish(Time(msg.header.stamp))

    def _process_scan(self, msg) -> None:
        """laserCallback: throttle, initialise on the first scan, add it, update the map."""
        from slam_predict.ros.conversions.geometry import time_from_ros

        self.laser_count += 1
        if self.laser_count % self.params.throttle_scans != 0:
            return
        stamp = time_from_ros(msg.header.stamp)
        if self.slam is None and not self._init_mapper(msg):
            return
        odom = self._lookup(self.params.odom_frame, self.params.base_frame, msg.header.stamp)
        if odom is None:
            LOG.warning("no %s -> %s transform at %.3f: scan skipped", self.params.odom_frame,
                        self.params.base_frame, stamp)
            return
        if len(msg.ranges) != self.slam.beam_angles.size:
            LOG.warning("scan with %d ranges, expected %d: skipped", len(msg.ranges),
                        self.slam.beam_angles.size)
            return
        ranges = prepare_ranges(msg.ranges, msg.range_min, msg.range_max, self.reverse)
        due = self.map_msg is None or stamp - self.last_map_update > self.slam.map_update_interval
        if self.slam.update(odom[0], ranges, stamp) is None:
            if due and self.map_msg is not None and self.slam.map_thread:
                self.update_map(stamp)   # slam_toolbox's map thread: no new scan needed
            return
        with self._lock:
            self.map_to_odom = self.slam.map_to_odom()
        if due:
            self.update_map(stamp)

    def _init_mapper(self, msg) -> bool:
        from slam_predict import slam

        lookup = self._lookup(self.params.base_frame, msg.header.frame_id, msg.header.stamp)
        if lookup is None:
            LOG.warning("cannot find the laser frame %s in %s: initialisation postponed",
                        msg.header.frame_id, self.params.base_frame)
            return False
        translation, rotation = lookup[1], lookup[2]
        laser, self.reverse = laser_geometry(rotation, translation, msg.angle_min,
                                             msg.angle_increment, len(msg.ranges), msg.range_max)
        if laser is None:
            LOG.warning("laser %s is not planar: initialisation postponed", msg.header.frame_id)
            return False
        self.slam = slam.create(self.choice.type, params=self.choice.params, laser=laser,
                                rng=np.random.default_rng(self.seed))
        stream = {k: v for k, v in self.slam.stats().items()
                  if k in ("random_stream", "drand48_seed")}
        LOG.info("%s initialised: %d beams, seed %d%s", self.slam.label, laser.beams, self.seed,
                 "".join(f", {k} {v}" for k, v in stream.items()))
        return True

    def _lookup(self, parent: str, child: str, stamp):
        """(planar pose (x, y, yaw), translation (3,), rotation 3 x 3) of child in parent."""
        deadline = time.monotonic() + TF_WAIT
        while True:
            try:
                tf = self.tf_buffer.lookup_transform(parent, child, stamp)
                break
            except Exception:  # tf2 LookupException / ExtrapolationException / ...
                if time.monotonic() > deadline or self.rospy.is_shutdown():
                    return None
                time.sleep(0.01)
        t, q = tf.transform.translation, tf.transform.rotation
        rotation = quaternion_matrix(q.x, q.y, q.z, q.w)
        yaw = math.atan2(rotation[1, 0], rotation[0, 0])
        return np.array([t.x, t.y, yaw]), np.array([t.x, t.y, t.z]), rotation

    def update_map(self, stamp: float) -> None:
        """updateMap: the back-end's map; publish entropy, map and metadata."""
        from std_msgs.msg import Float64

        from slam_predict.ros.conversions.slam import grid_to_ros

        entropy = self.slam.entropy()
        if entropy > 0.0:
            self._pubs["entropy"].publish(Float64(entropy))
        grid = self.slam.map()
        now = self.rospy.get_time()
        msg = grid_to_ros(grid, self.params.map_frame, now)
        with self._map_lock:
            self.map_msg = msg
        self.last_map_update = stamp
        self._pubs["map"].publish(msg)
        self._pubs["map_metadata"].publish(msg.info)

    def on_get_map(self, _request):
        """dynamic_map: the latest map (the call fails before the first map)."""
        from slam_predict.ros.conversions.slam import get_map_response

        with self._map_lock:
            msg = self.map_msg
        if msg is None or msg.info.width == 0:
            return None
        return get_map_response(msg)

    def publish_transform(self) -> None:
        """Broadcast map → odom stamped now + tf_delay (skipped when the stamp would repeat the
        previous one, as happens with sim time; tf2 would warn TF_REPEATED_DATA)."""
        from slam_predict.ros.conversions.geometry import transform_to_ros

        with self._lock:
            pose = self.map_to_odom.copy()
        stamp = self.rospy.get_time() + self.params.effective_tf_delay
        if stamp == self._last_tf_stamp:
            return
        self._last_tf_stamp = stamp
        self.tf_broadcaster.sendTransform(
            transform_to_ros(pose, stamp, self.params.map_frame, self.params.odom_frame))


def read_params(rospy_module, executable: str = "slam_gmapping"
                ) -> tuple[SlamChoice, SlamNodeParams, int | None]:
    """The back-end (``~type``) with its parameters, the node's parameters, and ``~seed``
    (None if unset), from the private namespace; a slam_toolbox executable (``executable`` in
    :data:`TOOLBOX_NODES`) runs Karto with its own scan gate."""
    from slam_predict import slam
    from slam_predict.config import from_dict
    from slam_predict.errors import InputError

    toolbox = TOOLBOX_NODES.get(executable)
    default_type = toolbox[0] if toolbox else "gmapping"
    name = str(rospy_module.get_param("~type", default_type))
    if toolbox and name != toolbox[0]:
        raise InputError(f"~type {name}: {executable} runs only {toolbox[0]} (slam_gmapping "
                         "runs the other back-ends)")
    params_class = type(slam.backend_class(name).default_params())

    def private(cls) -> dict:
        return {f.name: rospy_module.get_param("~" + f.name) for f in dataclasses.fields(cls)
                if f.name != "type" and rospy_module.has_param("~" + f.name)}

    params = slam.params_from_dict(name, private(params_class), f"~ ({name} parameters)")
    if toolbox and params.scan_gate not in toolbox[1]:
        LOG.info("%s: scan_gate %s replaced by the node's %s", executable, params.scan_gate,
                 toolbox[1][0])
        params = dataclasses.replace(params, scan_gate=toolbox[1][0])
    node = from_dict(SlamNodeParams, private(SlamNodeParams), "~ (SLAM node parameters)")
    return SlamChoice(name, params), node, rospy_module.get_param("~seed", None)


def main(argv=None, executable: str = "slam_gmapping") -> int:
    """Entry point of scripts/slam_gmapping and of the slam_toolbox executables (the node's
    default name is the executable's, slam_toolbox's launch files name it slam_toolbox)."""
    import rospy
    import tf2_ros

    from slam_predict.ros.node_start import start_node

    default_name = "slam_toolbox" if executable in TOOLBOX_NODES else executable
    params = start_node(rospy, default_name, executable,
                        lambda module: read_params(module, executable), argv)
    if params is None:
        return 2
    choice, node_params, seed = params
    if seed is None:
        seed = int(np.random.SeedSequence().entropy % (2 ** 31))
    gate = getattr(choice.params, "scan_gate", None)
    rospy.loginfo(f"{executable}: back-end {choice.type}, seed {seed}"
                  + (f", scan_gate {gate}" if gate else ""))
    tf_buffer = tf2_ros.Buffer(cache_time=rospy.Duration(30.0))
    tf2_ros.TransformListener(tf_buffer)
    from slam_predict import slam
    slam.backend_class(choice.type).warmup()   # before the first ~sim_ack
    node = SlamNode(choice, node_params, int(seed), rospy, tf_buffer,
                    tf2_ros.TransformBroadcaster())
    node.start()
    rospy.spin()
    return 0
