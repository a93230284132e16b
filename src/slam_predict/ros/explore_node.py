"""``explore``: frontier exploration as a ROS node (explore_lite's interface), running
:class:`slam_predict.explore.Explorer`.

* subscribes the map (``~costmap_topic``, default ``map``: the SLAM map);
* robot pose from tf ``map → ~robot_base_frame``;
* an action client of ``move_base`` (MoveBaseAction) sends the goals; the first plan's length
  (for the goal time limit) comes from ``move_base/make_plan`` (straight-line distance when the
  service is missing);
* publishes ``~frontiers`` (visualization_msgs/MarkerArray, when ``~visualize``) and, latched,
  ``~status`` (std_msgs/String: ``exploring`` then the stop reason, e.g. ``no_frontiers``);
* ``~sim_ack`` (std_msgs/Time, latched) after every tick, for a lockstep stage_sim
  (:mod:`slam_predict.ros.lockstep`; "idle forever" once exploration has stopped).

Parameters: the private namespace as an :class:`ExploreConfig` (config/explore.yaml), plus
``~seed`` (int). The explorer is stepped at 5 Hz of ROS (sim) time.
"""
from __future__ import annotations

import logging
import math
import threading

import numpy as np

from slam_predict.explore.explorer import ExploreConfig, Explorer
from slam_predict.ros.lockstep import AckPublisher, SimTicker

LOG = logging.getLogger(__name__)
TICK_HZ = 5.0
# goal status as the explorer reads it: actionlib's GoalStatus, with SimpleActionClient's
# get_state() folding (RECALLING -> PENDING, PREEMPTING -> ACTIVE) and REJECTED, LOST ->
# ABORTED, RECALLED -> PREEMPTED
ACTION_TO_STATUS = {7: 0, 6: 1, 5: 4, 9: 4, 8: 2}


class ActionGoalClient:
    """The explorer's goal client over actionlib's ActionClient, tracking the goal handle of the
    latest goal itself and asking it for its status (no transition callbacks).

    SimpleActionClient would do the same, but when a goal is replaced while move_base's status
    thread is still delivering an update of the old goal, it logs "Got a transition callback on
    a goal handle that we're not tracking" at ERROR level for that harmless, expected message;
    without callbacks the old goal's updates reach nobody."""

    def __init__(self, action_client, make_plan=None, frame_id: str = "map", robot_pose=None):
        self.client = action_client
        self.make_plan = make_plan
        self.frame_id = frame_id
        self.robot_pose = robot_pose
        self.handle = None
        self.length: float | None = None

    def send_goal(self, target, t: float) -> None:
        from slam_predict.ros.conversions.nav import goal_to_ros

        self.handle = self.client.send_goal(goal_to_ros(target, self.frame_id, t))
        self.length = self._plan_length(target)

    def _plan_length(self, target) -> float | None:
        start = self.robot_pose() if self.robot_pose is not None else None
        if self.make_plan is not None:
            try:
                length = self.make_plan(target)
                if length is not None:
                    return length
            except Exception as exc:  # service missing or failing: fall back
                LOG.debug("make_plan failed: %s", exc)
        if start is None:
            return None
        return float(math.hypot(target[0] - start[0], target[1] - start[1]))

    def cancel(self, t: float) -> None:
        if self.handle is not None:
            self.handle.cancel()

    def status(self) -> int | None:
        if self.handle is None:
            return None
        state = int(self.handle.get_goal_status())
        return ACTION_TO_STATUS.get(state, state)

    def plan_length(self) -> float | None:
        return self.length


class ExploreNode:
    """Holds the Explorer; ROS objects are passed in."""

    def __init__(self, cfg: ExploreConfig, rospy_module, tf_buffer, client: ActionGoalClient,
                 rng: np.random.Generator, map_frame: str = "map"):
        self.cfg = cfg
        self.rospy = rospy_module
        self.tf_buffer = tf_buffer
        self.client = client
        self.explorer = Explorer(cfg, client, rng)
        self.map_frame = map_frame
        self.grid = None
        self.lock = threading.Lock()
        self._shown = None
        self._pubs = {}
        self._ticker = None

    def start(self) -> None:
        from nav_msgs.msg import OccupancyGrid
        from std_msgs.msg import String
        from visualization_msgs.msg import MarkerArray

        rp = self.rospy
        self._pubs = {"frontiers": rp.Publisher("~frontiers", MarkerArray, queue_size=1),
                      "status": rp.Publisher("~status", String, queue_size=1, latch=True)}
        self._pubs["status"].publish(String("exploring"))
        rp.Subscriber(self.cfg.costmap_topic, OccupancyGrid, self.on_map, queue_size=1)
        self._ticker = SimTicker(rp, 1.0 / TICK_HZ, self.tick, AckPublisher(rp))
        self._ticker.start()

    def on_map(self, msg) -> None:
        from slam_predict.ros.conversions.slam import grid_from_ros

        grid = grid_from_ros(msg)
        with self.lock:
            self.grid = grid
            self.map_frame = msg.header.frame_id or self.map_frame
            self.client.frame_id = self.map_frame

    def robot_pose(self) -> np.ndarray | None:
        from slam_predict.ros.conversions.geometry import transform_from_ros

        try:
            tf = self.tf_buffer.lookup_transform(self.map_frame, self.cfg.robot_base_frame,
                                                 self.rospy.Time(0))
        except Exception:  # tf2 exceptions: no pose yet
            return None
        return np.asarray(transform_from_ros(tf).pose, dtype=float)

    def tick(self, now: float | None = None) -> None:
        """Step the explorer; publish frontiers; report the end.

        ``now``: the tick's sim time (s) from the ticker's /clock (rospy's own clock may
        lag it by a message); None = ``rospy.get_time()``."""
        from std_msgs.msg import String

        from slam_predict.ros.conversions.nav import frontiers_to_ros

        pose = self.robot_pose()
        with self.lock:
            grid = self.grid
        if pose is None or grid is None or self.explorer.done:
            return
        now = self.rospy.get_time() if now is None else float(now)
        self.explorer.step(now, grid, pose)
        frontiers = self.explorer.frontiers
        if self.cfg.visualize and frontiers is not self._shown:
            self._shown = frontiers
            flags = [self.explorer.is_blacklisted(f) for f in frontiers]
            self._pubs["frontiers"].publish(frontiers_to_ros(frontiers, self.map_frame, now, flags))
        if self.explorer.done:
            reason = self.explorer.log.stop_reason
            self.rospy.loginfo(f"explore: Exploration stopped ({reason}); goals "
                               f"{self.explorer.log.counts()}")
            self._pubs["status"].publish(String(reason))
            if self._ticker is not None:
                self._ticker.stop()


def read_config(rospy_module) -> ExploreConfig:
    """ExploreConfig from the private namespace (``seed`` excluded)."""
    from slam_predict.config import from_dict

    tree = dict(rospy_module.get_param("~", {}) or {})
    tree.pop("seed", None)
    if ("max_vel_x" not in tree
            and rospy_module.has_param("/move_base/TrajectoryPlannerROS/max_vel_x")):
        tree["max_vel_x"] = rospy_module.get_param("/move_base/TrajectoryPlannerROS/max_vel_x")
    return from_dict(ExploreConfig, tree, f"{rospy_module.get_name()} parameters")


def main(argv=None) -> int:
    """Entry point of scripts/explore."""
    import actionlib
    import rospy
    import tf2_ros
    from geometry_msgs.msg import PoseStamped
    from move_base_msgs.msg import MoveBaseAction
    from nav_msgs.srv import GetPlan

    from slam_predict.ros.conversions.nav import plan_from_ros, pose_stamped_to_ros
    from slam_predict.ros.node_start import start_node

    cfg = start_node(rospy, "explore", "explore", read_config, argv)
    if cfg is None:
        return 2
    seed = int(rospy.get_param("~seed", 0))
    tf_buffer = tf2_ros.Buffer(cache_time=rospy.Duration(30.0))
    tf2_ros.TransformListener(tf_buffer)
    action = actionlib.ActionClient("move_base", MoveBaseAction)
    rospy.loginfo("explore: waiting for move_base")
    action.wait_for_server()
    service = rospy.ServiceProxy("move_base/make_plan", GetPlan)

    def plan_length(target) -> float | None:
        goal = pose_stamped_to_ros(target, client.frame_id, rospy.get_time())
        start = PoseStamped()   # empty frame: from the robot
        poses = plan_from_ros(service(start, goal, 0.0).plan)
        if len(poses) < 2:
            return None
        return float(np.sum(np.hypot(*np.diff(poses[:, :2], axis=0).T)))

    client = ActionGoalClient(action, plan_length)
    node = ExploreNode(cfg, rospy, tf_buffer, client, np.random.default_rng(seed))
    client.robot_pose = node.robot_pose
    node.start()
    rospy.spin()
    return 0
