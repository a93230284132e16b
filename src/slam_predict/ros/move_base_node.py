"""``move_base``: a drop-in for ROS move_base running :class:`slam_predict.nav.Navigator`.

Interface (ros_interfaces.md §3.1), names relative to the node (``move_base``):

* action server ``move_base`` (move_base_msgs/MoveBaseAction): a new goal preempts the current
  one; results SUCCEEDED / ABORTED / PREEMPTED with move_base's texts; feedback base_position;
  a goal with an invalid quaternion is aborted with move_base's text;
* subscribes ``move_base_simple/goal`` (PoseStamped → goal), ``map`` (the static layers),
  ``scan`` (the obstacle layers; remap to stage_sim's ``base_scan``), ``odom`` (velocity);
* publishes ``cmd_vel`` at ``controller_frequency`` (zero when idle, which also paces a
  lockstep stage_sim), ``~global_costmap/costmap`` and ``~local_costmap/costmap`` at their
  ``publish_frequency``, ``~NavfnROS/plan``, ``~TrajectoryPlannerROS/global_plan`` and
  ``~TrajectoryPlannerROS/local_plan``, ``~current_goal``, and with each costmap
  ``~<costmap>/footprint`` (geometry_msgs/PolygonStamped: the padded footprint at the robot's
  pose in that costmap's frame, as costmap_2d);
* services ``~make_plan`` (nav_msgs/GetPlan) and ``~clear_costmaps`` (std_srvs/Empty);
* ``~sim_ack`` (std_msgs/Time) after every controller cycle and ``~scan_ack`` (the stamp of
  each scan once it is in the costmaps), for a lockstep stage_sim
  (:mod:`slam_predict.ros.lockstep`);
* tf: ``map → odom`` and ``odom → base_link`` (frames from the costmap parameters).

Parameters: the whole private namespace is read as a :class:`MoveBaseConfig` (load the
config/*.yaml files into it; launch/move_base.launch does). Time is ROS time (sim time with
stage_sim); the same Navigator code runs in the in-process loop.
"""
from __future__ import annotations

import logging
import threading
import time

import numpy as np

from slam_predict.nav.config import MoveBaseConfig
from slam_predict.nav.navigator import TEXT_INVALID_QUATERNION, TEXT_NEW_GOAL, GoalStatus, Navigator
from slam_predict.ros.lockstep import AckPublisher, SimTicker

LOG = logging.getLogger(__name__)
TF_WAIT = 0.2  # wall s to wait for a scan's transform


class MoveBaseNode:
    """The node's logic around one Navigator; ROS objects are passed in (testable)."""

    def __init__(self, cfg: MoveBaseConfig, rospy_module, tf_buffer):
        self.cfg = cfg
        self.rospy = rospy_module
        self.tf_buffer = tf_buffer
        self.navigator = Navigator(cfg)
        self.global_frame = cfg.global_costmap.global_frame
        self.local_frame = cfg.local_costmap.global_frame
        self.base_frame = cfg.global_costmap.robot_base_frame
        self.lock = threading.RLock()
        self.velocity = (0.0, 0.0)
        self.handle = None
        self.record = None
        self._pubs = {}
        self._published_plan = None
        self._next_publish = {"global": 0.0, "local": 0.0}
        self._ticker = None
        self._scan_ack = None

    # ------------------------------------------------------------------------------ set-up
    def start(self) -> None:
        """Advertise, subscribe, start the action server and the control timer."""
        import actionlib
        from geometry_msgs.msg import PolygonStamped, PoseStamped, Twist
        from move_base_msgs.msg import MoveBaseAction
        from nav_msgs.msg import OccupancyGrid, Odometry, Path
        from nav_msgs.srv import GetPlan
        from sensor_msgs.msg import LaserScan
        from std_srvs.srv import Empty

        from slam_predict.ros.conversions.slam import NumpyOccupancyGrid

        rp = self.rospy
        self._pubs = {
            "cmd_vel": rp.Publisher("cmd_vel", Twist, queue_size=1),
            "global": rp.Publisher("~global_costmap/costmap", NumpyOccupancyGrid, queue_size=1,
                                   latch=True),
            "local": rp.Publisher("~local_costmap/costmap", NumpyOccupancyGrid, queue_size=1),
            "plan": rp.Publisher("~NavfnROS/plan", Path, queue_size=1, latch=True),
            "tp_global": rp.Publisher("~TrajectoryPlannerROS/global_plan", Path, queue_size=1),
            "tp_local": rp.Publisher("~TrajectoryPlannerROS/local_plan", Path, queue_size=1),
            "goal": rp.Publisher("~current_goal", PoseStamped, queue_size=1, latch=True),
            "global_footprint": rp.Publisher("~global_costmap/footprint", PolygonStamped,
                                             queue_size=1),
            "local_footprint": rp.Publisher("~local_costmap/footprint", PolygonStamped,
                                            queue_size=1),
        }
        rp.Subscriber("map", OccupancyGrid, self.on_map, queue_size=1)
        rp.Subscriber("scan", LaserScan, self.on_scan, queue_size=1)
        self._scan_ack = AckPublisher(rp, "~scan_ack")
        self._scan_ack.publish(0.0)   # ready: no scan pending
        rp.Subscriber("odom", Odometry, self.on_odom, queue_size=1)
        rp.Subscriber("move_base_simple/goal", PoseStamped, self.on_simple_goal, queue_size=1)
        rp.Service("~make_plan", GetPlan, self.on_make_plan)
        rp.Service("~clear_costmaps", Empty, self.on_clear_costmaps)
        self.server = actionlib.ActionServer("move_base", MoveBaseAction, self.on_goal,
                                             self.on_cancel, auto_start=False)
        self.server.start()
        self._ticker = SimTicker(rp, 1.0 / self.cfg.controller_frequency, self.tick,
                                 AckPublisher(rp))
        self._ticker.start()

    # ------------------------------------------------------------------------------ inputs
    def on_map(self, msg) -> None:
        from slam_predict.ros.conversions.slam import grid_from_ros

        grid = grid_from_ros(msg)
        with self.lock:
            self.navigator.set_map(grid)

    def on_odom(self, msg) -> None:
        self.velocity = (float(msg.twist.twist.linear.x), float(msg.twist.twist.angular.z))

    def on_scan(self, msg) -> None:
        """Add the scan to the costmaps' obstacle layers, then ``~scan_ack`` its stamp."""
        try:
            self._add_scan(msg)
        finally:
            if self._scan_ack is not None:
                self._scan_ack.publish(msg.header.stamp.to_sec())

    def _add_scan(self, msg) -> None:
        from slam_predict.ros.conversions.sensor import scan_from_ros

        sensor = self.lookup(self.local_frame, msg.header.frame_id, msg.header.stamp, TF_WAIT)
        map_T_odom = self.lookup(self.global_frame, self.local_frame)
        if sensor is None or map_T_odom is None:
            return
        scan = scan_from_ros(msg)
        with self.lock:
            self.navigator.add_scan(scan.ranges, scan.angles(), scan.range_min, scan.range_max,
                                    sensor, np.zeros(3), map_T_odom)

    def lookup(self, parent: str, child: str, stamp=None, wait: float = 0.0) -> np.ndarray | None:
        """Planar pose (x, y, yaw) of ``child`` in ``parent`` (latest when ``stamp`` is None)."""
        from slam_predict.ros.conversions.geometry import transform_from_ros

        stamp = self.rospy.Time(0) if stamp is None else stamp
        deadline = time.monotonic() + wait
        while True:
            try:
                tf = self.tf_buffer.lookup_transform(parent, child, stamp)
                return np.asarray(transform_from_ros(tf).pose, dtype=float)
            except Exception:  # tf2 Lookup / Extrapolation / Connectivity exceptions
                if time.monotonic() >= deadline or self.rospy.is_shutdown():
                    return None
                time.sleep(0.01)

    # ------------------------------------------------------------------------------- goals
    def on_goal(self, handle) -> None:
        """A new action goal: preempt the current one, start this one."""
        from slam_predict.ros.conversions.nav import goal_from_ros

        parsed = goal_from_ros(handle.get_goal())
        handle.set_accepted()
        if parsed is None:
            handle.set_aborted(None, TEXT_INVALID_QUATERNION)
            return
        self._start_goal(parsed[0], parsed[1], handle)

    def on_simple_goal(self, msg) -> None:
        """move_base_simple/goal: a goal without an action client."""
        from slam_predict.ros.conversions.nav import pose_stamped_from_ros

        parsed = pose_stamped_from_ros(msg)
        if parsed is None:
            self.rospy.logerr(TEXT_INVALID_QUATERNION)
            return
        self._start_goal(parsed[0], parsed[1], None)

    def _start_goal(self, pose, frame: str, handle) -> None:
        from slam_predict.geometry import compose
        from slam_predict.ros.conversions.nav import pose_stamped_to_ros

        if frame and frame != self.global_frame:
            link = self.lookup(self.global_frame, frame, None, TF_WAIT)
            if link is None:
                if handle is not None:
                    handle.set_aborted(None, f"Could not transform the goal from {frame}")
                return
            pose = compose(link, pose)
        now = self.rospy.get_time()
        with self.lock:
            previous, self.handle = self.handle, handle
            self.record = self.navigator.send_goal(pose, now)
        if previous is not None:   # outside self.lock (lock order: actionlib's, then ours)
            previous.set_canceled(None, TEXT_NEW_GOAL)
        self._pubs["goal"].publish(pose_stamped_to_ros(pose, self.global_frame, now))

    def on_cancel(self, handle) -> None:
        with self.lock:
            current = self.handle
            if current is None or handle.get_goal_id().id != current.get_goal_id().id:
                return
            self.navigator.cancel_goal(self.rospy.get_time())
            self.handle = self.record = None
        current.set_canceled(None, "")

    # ------------------------------------------------------------------------------- cycle
    def tick(self, now: float | None = None) -> None:
        """One controller cycle: step the navigator, publish the command and what changed.

        ``now``: the tick's sim time (s) from the ticker's /clock (rospy's own clock may
        lag it by a message); None = ``rospy.get_time()``."""
        from slam_predict.ros.conversions.geometry import twist_to_ros

        map_T_odom = self.lookup(self.global_frame, self.local_frame)
        odom_pose = self.lookup(self.local_frame, self.base_frame)
        if map_T_odom is None or odom_pose is None:
            return
        now = self.rospy.get_time() if now is None else float(now)
        with self.lock:
            cmd = self.navigator.step(now, odom_pose, map_T_odom, self.velocity)
            handle, record = self.handle, self.record
            if record is not None and record.done:
                self.handle = self.record = None
        # actionlib calls on_goal / on_cancel holding its own lock, which then take self.lock:
        # goal handles are only touched outside self.lock, or that lock order inverts (deadlock)
        self._report(handle, record, map_T_odom, odom_pose, now)
        self._pubs["cmd_vel"].publish(twist_to_ros(cmd))
        self._publish_maps(now)
        self._publish_footprints(map_T_odom, odom_pose, now)

    def _publish_footprints(self, map_T_odom, odom_pose, now: float) -> None:
        """~<costmap>/footprint: the padded footprint at the robot's pose, per costmap frame."""
        from slam_predict.geometry import compose
        from slam_predict.ros.conversions.nav import polygon_to_ros

        robot = {"global": compose(map_T_odom, odom_pose), "local": odom_pose}
        for key, costmap, frame in (("global", self.navigator.global_costmap, self.global_frame),
                                    ("local", self.navigator.local_costmap, self.local_frame)):
            publisher = self._pubs[key + "_footprint"]
            if _listened(publisher):
                publisher.publish(polygon_to_ros(costmap.footprint, robot[key], frame, now))

    def _report(self, handle, record, map_T_odom, odom_pose, now: float) -> None:
        """Finish the action goal when the navigator has; otherwise send feedback (call
        without holding self.lock)."""
        from move_base_msgs.msg import MoveBaseFeedback

        from slam_predict.geometry import compose
        from slam_predict.ros.conversions.nav import pose_stamped_to_ros

        if record is None:
            return
        if record.done:
            if handle is not None:
                if record.status == GoalStatus.SUCCEEDED:
                    handle.set_succeeded(None, record.text)
                elif record.status == GoalStatus.ABORTED:
                    handle.set_aborted(None, record.text)
            return
        if handle is not None:
            feedback = MoveBaseFeedback()
            feedback.base_position = pose_stamped_to_ros(compose(map_T_odom, odom_pose),
                                                         self.global_frame, now)
            with self.server.lock:   # actionlib's lock first, then ours: no goal swap meanwhile
                with self.lock:
                    current = self.handle is handle
                if current:
                    handle.publish_feedback(feedback)

    def _publish_maps(self, now: float) -> None:
        from slam_predict.ros.conversions.nav import costmap_to_ros, plan_to_ros

        nav, pubs = self.navigator, self._pubs
        for key, costmap, frame in (("global", nav.global_costmap, self.global_frame),
                                    ("local", nav.local_costmap, self.local_frame)):
            freq = costmap.cfg.publish_frequency
            if freq > 0 and now >= self._next_publish[key]:
                self._next_publish[key] = now + 1.0 / freq
                if _listened(pubs[key]):   # a 4000 x 4000 grid costs ~0.1 s to convert
                    with self.lock:
                        msg = costmap_to_ros(costmap.costmap, frame, now)
                    pubs[key].publish(msg)
        if nav.plan is not None and nav.plan is not self._published_plan:
            self._published_plan = nav.plan   # latched: published even without subscribers
            pubs["plan"].publish(plan_to_ros(nav.plan.poses, self.global_frame, now))
        controller = nav.controller
        if _listened(pubs["tp_global"]):
            pubs["tp_global"].publish(plan_to_ros(controller.transformed_plan, self.local_frame,
                                                  now))
        if _listened(pubs["tp_local"]):
            pubs["tp_local"].publish(plan_to_ros(controller.local_plan, self.local_frame, now))

    # ---------------------------------------------------------------------------- services
    def on_make_plan(self, request):
        """~make_plan: a plan from start (empty frame: the robot) to goal, with tolerance."""
        from nav_msgs.srv import GetPlanResponse

        from slam_predict.geometry import compose
        from slam_predict.ros.conversions.geometry import pose_from_ros
        from slam_predict.ros.conversions.nav import plan_to_ros

        response = GetPlanResponse()
        response.plan.header.frame_id = self.global_frame
        if request.start.header.frame_id:
            start = pose_from_ros(request.start.pose)
        else:
            map_T_odom = self.lookup(self.global_frame, self.local_frame)
            odom_pose = self.lookup(self.local_frame, self.base_frame)
            if map_T_odom is None or odom_pose is None:
                return response
            start = compose(map_T_odom, odom_pose)
        goal = pose_from_ros(request.goal.pose)
        tolerance = float(request.tolerance) if request.tolerance > 0 else None
        with self.lock:
            plan = self.navigator.make_plan(start, goal, tolerance)
        if plan is not None:
            response.plan = plan_to_ros(plan.poses, self.global_frame, self.rospy.get_time())
        return response

    def on_clear_costmaps(self, _request):
        from std_srvs.srv import EmptyResponse

        with self.lock:
            self.navigator.clear_costmaps()
        return EmptyResponse()


def _listened(publisher) -> bool:
    """True when ``publisher`` has a subscriber (or cannot tell, e.g. a test double)."""
    count = getattr(publisher, "get_num_connections", None)
    return count is None or count() > 0


def read_config(rospy_module) -> MoveBaseConfig:
    """The private namespace as a MoveBaseConfig (InputError on unknown or bad keys)."""
    from slam_predict.config import from_dict

    tree = rospy_module.get_param("~", {}) or {}
    return from_dict(MoveBaseConfig, dict(tree), f"{rospy_module.get_name()} parameters")


def main(argv=None) -> int:
    """Entry point of scripts/move_base."""
    import rospy
    import tf2_ros

    from slam_predict.ros.node_start import start_node

    cfg = start_node(rospy, "move_base", "move_base", read_config, argv)
    if cfg is None:
        return 2
    tf_buffer = tf2_ros.Buffer(cache_time=rospy.Duration(30.0))
    tf2_ros.TransformListener(tf_buffer)
    from slam_predict.ros.lockstep import warm
    # before the first ~sim_ack
    warm("slam_predict.nav.kernels", "slam_predict.nav.footprint_helper")
    node = MoveBaseNode(cfg, rospy, tf_buffer)
    node.start()
    rospy.loginfo(f"move_base: {cfg.base_global_planner} + {cfg.base_local_planner}, "
                  f"controller {cfg.controller_frequency:g} Hz")
    rospy.spin()
    return 0


__all__ = ["MoveBaseNode", "main", "read_config"]
