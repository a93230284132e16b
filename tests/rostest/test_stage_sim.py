#!/usr/bin/env python3
"""rostest: stage_sim publishes scans at 10 Hz sim time, odometry = ground truth (model none),
the full tf chain, and stops the robot when cmd_vel goes silent."""
import threading
import unittest

import numpy as np
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan

from slam_predict.geometry import compose, wrap_angle
from slam_predict.ros.conversions.geometry import odometry_from_ros, transform_from_ros

START = np.array([-2.0, 0.0, 0.0])  # tests/data/stage_sim_room.world


class Recorder:
    def __init__(self, topic, kind):
        self.messages = []
        self.lock = threading.Lock()
        rospy.Subscriber(topic, kind, self.on_message, queue_size=100)

    def on_message(self, msg):
        with self.lock:
            self.messages.append(msg)

    def take(self):
        with self.lock:
            out, self.messages = self.messages, []
        return out


def wait_sim(seconds):
    """Wait ``seconds`` of sim time."""
    end = rospy.Time.now() + rospy.Duration(seconds)
    while not rospy.is_shutdown() and rospy.Time.now() < end:
        rospy.sleep(0.05)


class StageSimTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.scans = Recorder("base_scan", LaserScan)
        cls.odom = Recorder("odom", Odometry)
        cls.truth = Recorder("base_pose_ground_truth", Odometry)
        cls.cmd = rospy.Publisher("cmd_vel", Twist, queue_size=1)
        cls.tf_buffer = tf2_ros.Buffer()
        cls.tf_listener = tf2_ros.TransformListener(cls.tf_buffer)
        rospy.wait_for_message("base_scan", LaserScan, timeout=60.0)

    def drive(self, v, w, seconds):
        msg = Twist()
        msg.linear.x, msg.angular.z = v, w
        end = rospy.Time.now() + rospy.Duration(seconds)
        while not rospy.is_shutdown() and rospy.Time.now() < end:
            self.cmd.publish(msg)
            rospy.sleep(0.05)

    def test_1_scan_rate_and_size(self):
        self.scans.take()
        wait_sim(3.0)
        scans = self.scans.take()
        stamps = np.array([m.header.stamp.to_sec() for m in scans])
        rate = (len(stamps) - 1) / (stamps[-1] - stamps[0])
        self.assertAlmostEqual(rate, 10.0, delta=1.0)
        for msg in scans:
            self.assertEqual(len(msg.ranges), 541)
            self.assertEqual(msg.header.frame_id, "base_laser_link")
        self.assertAlmostEqual(scans[0].angle_max - scans[0].angle_min, np.radians(270), 4)

    def test_2_odometry_matches_ground_truth(self):
        self.odom.take()
        self.truth.take()
        self.drive(0.4, 0.3, 3.0)
        odom = {m.header.stamp.to_nsec(): odometry_from_ros(m) for m in self.odom.take()}
        truth = {m.header.stamp.to_nsec(): odometry_from_ros(m) for m in self.truth.take()}
        common = sorted(set(odom) & set(truth))
        self.assertGreater(len(common), 20)
        moved = 0.0
        for stamp in common:
            expected = compose(START, odom[stamp].pose)
            got = truth[stamp].pose
            np.testing.assert_allclose(got[:2], expected[:2], atol=1e-6)
            self.assertLess(abs(float(wrap_angle(got[2] - expected[2]))), 1e-6)
            moved = max(moved, float(np.hypot(*(got[:2] - START[:2]))))
            self.assertEqual(odom[stamp].child_frame_id, "base_footprint")
        self.assertGreater(moved, 0.3)

    def test_3_tf_chain(self):
        frames = [("odom", "base_footprint"), ("base_footprint", "base_link"),
                  ("base_link", "base_laser_link"), ("odom", "base_laser_link")]
        for parent, child in frames:
            tf = self.tf_buffer.lookup_transform(parent, child, rospy.Time(0),
                                                 rospy.Duration(10.0))
            data = transform_from_ros(tf)
            self.assertEqual((data.parent, data.child), (parent, child))
        odom = odometry_from_ros(rospy.wait_for_message("odom", Odometry, timeout=10.0))
        self.assertGreater(odom.stamp, 0.0)

    def test_4_robot_stops_when_cmd_vel_goes_silent(self):
        self.drive(0.5, 0.0, 1.0)
        wait_sim(1.5)  # watchdog 0.2 s, then deceleration at 1.5 m/s²
        quiet_from = rospy.Time.now().to_sec()
        wait_sim(1.5)
        truth = [odometry_from_ros(m) for m in self.truth.take()]
        truth = [t for t in truth if t.stamp >= quiet_from]  # messages may arrive late
        self.assertGreater(len(truth), 5)
        poses = np.array([t.pose for t in truth])
        self.assertLess(float(np.abs(poses - poses[0]).max()), 1e-12, poses - poses[0])
        for t in truth:
            self.assertEqual(t.twist, (0.0, 0.0, 0.0))
        odom = odometry_from_ros(rospy.wait_for_message("odom", Odometry, timeout=10.0))
        self.assertEqual(odom.twist, (0.0, 0.0, 0.0))


if __name__ == "__main__":
    rospy.init_node("test_stage_sim")
    rostest.rosrun("slam_predict", "test_stage_sim", StageSimTest)
