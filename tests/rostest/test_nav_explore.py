#!/usr/bin/env python3
"""rostest: move_base and explore on the tiny world (see nav_explore.test)."""
import math
import time
import unittest

import actionlib
import numpy as np
import rospy
import rostest
import tf2_ros
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import Twist
from move_base_msgs.msg import MoveBaseAction
from nav_msgs.msg import OccupancyGrid
from std_msgs.msg import String

from slam_predict.nav.config import load_nav_config
from slam_predict.nav.navigator import TEXT_NO_PLAN, TEXT_REACHED
from slam_predict.ros.conversions.geometry import transform_to_ros
from slam_predict.ros.conversions.nav import goal_to_ros
from slam_predict.world.load import load_plan
from slam_predict.world.start import clearance_m


class NavExploreTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("test_nav_explore")
        cls.world = load_plan(rospy.get_param("~world"))
        broadcaster = tf2_ros.StaticTransformBroadcaster()
        broadcaster.sendTransform(transform_to_ros(cls.world.start_pose, 0.0, "map", "odom"))
        cls.broadcaster = broadcaster
        cls.commands = []
        rospy.Subscriber("/cmd_vel", Twist, lambda m: cls.commands.append(
            (rospy.get_time(), m.linear.x, m.angular.z)))
        cls.client = actionlib.SimpleActionClient("move_base", MoveBaseAction)
        assert cls.client.wait_for_server(rospy.Duration(60.0)), "no move_base action server"
        rospy.wait_for_message("/move_base/global_costmap/costmap", OccupancyGrid, timeout=60.0)

    def goal_in_a_room(self):
        """The free cell of largest clearance at least 3 m from the start."""
        clear = clearance_m(self.world)
        rows, cols = np.nonzero(clear > 0.5)
        xy = self.world.cell_to_world(np.stack([rows, cols], axis=1))
        far = np.hypot(*(xy - self.world.start_pose[:2]).T) > 3.0
        best = np.argmax(np.where(far, clear[rows, cols], -1))
        return float(xy[best, 0]), float(xy[best, 1]), 0.5

    def run_goal(self, target, timeout):
        self.client.send_goal(goal_to_ros(target, "map", rospy.get_time()))
        self.assertTrue(self.client.wait_for_result(rospy.Duration(timeout)), "no result")
        return self.client.get_state(), self.client.get_goal_status_text()

    def test_1_explorer_finishes(self):
        deadline = time.time() + 60.0
        status = None
        while time.time() < deadline:
            status = rospy.wait_for_message("/explore/status", String, timeout=30.0).data
            if status != "exploring":
                break
            time.sleep(0.5)
        self.assertEqual(status, "no_frontiers")

    def test_2_reachable_goal_succeeds(self):
        target = self.goal_in_a_room()
        state, text = self.run_goal(target, 120.0)
        self.assertEqual(state, GoalStatus.SUCCEEDED, text)
        self.assertEqual(text, TEXT_REACHED)

    def test_3_goal_off_the_map_aborts(self):
        state, text = self.run_goal((500.0, 500.0, 0.0), 120.0)
        self.assertEqual(state, GoalStatus.ABORTED)
        self.assertEqual(text, TEXT_NO_PLAN)

    def test_4_commands_within_limits(self):
        from pathlib import Path
        cfg = load_nav_config(Path(__file__).resolve().parents[2] / "config")
        tp = cfg.TrajectoryPlannerROS
        self.assertGreater(len(self.commands), 10)
        cmds = np.array(self.commands)
        self.assertTrue(np.all(cmds[:, 1] <= tp.max_vel_x + 1e-6))
        self.assertTrue(np.all(np.abs(cmds[:, 2]) <= tp.max_vel_theta + 1e-6))
        moving = np.abs(cmds[:, 1]) > 0
        self.assertTrue(moving.any())


if __name__ == "__main__":
    rostest.rosrun("slam_predict", "test_nav_explore", NavExploreTest)
