#!/usr/bin/env python3
"""rostest: with ground_truth_source:=pose the record's ground truth is the mocap topic's pose
corrected by the marker offset, i.e. the simulator's truth expressed in the mocap frame."""
import shutil
import threading
import time
import unittest
from pathlib import Path

import numpy as np
import rospy
import rostest
from nav_msgs.msg import Odometry

from slam_predict.collect import record as rec
from slam_predict.geometry import compose, wrap_angle
from slam_predict.ros.conversions.geometry import odometry_from_ros


class MocapPose(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.truth = {}
        cls.lock = threading.Lock()
        rospy.Subscriber("base_pose_ground_truth", Odometry, cls.on_truth, queue_size=1000)
        cls.out = Path(rospy.get_param("~out"))
        cls.frame = np.asarray(rospy.get_param("~frame"), float)
        deadline = time.monotonic() + float(rospy.get_param("~wait"))
        while time.monotonic() < deadline and not (cls.out / "run.json").exists():
            time.sleep(0.5)

    @classmethod
    def on_truth(cls, msg):
        data = odometry_from_ros(msg)
        with cls.lock:
            cls.truth[round(data.stamp, 6)] = data.pose

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.out.parents[1], ignore_errors=True)

    def test_ground_truth_comes_from_the_pose_topic(self):
        self.assertTrue((self.out / "run.json").is_file(), f"no record in {self.out}")
        record, traj = rec.load_record(self.out)
        gt = record["ros"]["ground_truth"]
        self.assertEqual((gt["source"], gt["topic"]), ("pose", "/mocap/pose"))
        self.assertEqual(record["ros"]["samples_dropped"], 0)
        with self.lock:
            truth = dict(self.truth)
        common = [(i, truth[round(t, 6)]) for i, t in enumerate(traj.t) if round(t, 6) in truth]
        self.assertGreater(len(common), 0.8 * len(traj.t), "too few truth messages seen")
        moved = 0.0
        for i, true_pose in common:
            expected = compose(self.frame, true_pose)      # truth in the mocap frame
            got = traj.ground_truth[i]
            np.testing.assert_allclose(got[:2], expected[:2], atol=1e-6)
            self.assertLess(abs(float(wrap_angle(got[2] - expected[2]))), 1e-6)
            moved = max(moved, float(np.hypot(*(true_pose[:2] - common[0][1][:2]))))
            # and it is not the simulator's topic itself
            self.assertGreater(float(np.hypot(*(got[:2] - true_pose[:2]))), 5.0)
        self.assertGreater(moved, 0.3, "the robot did not move: a weak test")
        # distance is frame-independent: same as along the simulator's truth
        true_path = np.array([p for _, p in common])
        self.assertAlmostEqual(record["distance_m"], rec.path_length(true_path), delta=0.05)


if __name__ == "__main__":
    rospy.init_node("test_mocap_pose")
    rostest.rosrun("slam_predict", "test_mocap_pose", MocapPose)
