#!/usr/bin/env python3
"""rostest: batch_explore.launch slam_type:=karto writes a valid record of a short tiny-world
exploration made with our sync_slam_toolbox_node (Karto), with the hashes of
config/collect_karto.yaml."""
import shutil
import time
import unittest
from pathlib import Path

import numpy as np
import rospy
import rostest

from slam_predict.collect import record as rec
from slam_predict.collect.settings import SLAM_SETTINGS, load_settings


class BatchExploreKarto(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.out = Path(rospy.get_param("~out"))
        cls.max_sim_time = float(rospy.get_param("~max_sim_time"))
        deadline = time.monotonic() + float(rospy.get_param("~wait"))
        while time.monotonic() < deadline and not (cls.out / "summary.csv").exists():
            time.sleep(0.5)
        cls.run_dir = cls.out / "tiny" / "run_000"

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.out, ignore_errors=True)

    def test_the_record_is_kartos(self):
        self.assertTrue((self.out / "summary.csv").is_file(), f"no summary.csv in {self.out}")
        record, traj = rec.load_record(self.run_dir)
        self.assertEqual(record["slam"]["type"], "karto")
        hashes = load_settings(SLAM_SETTINGS["karto"]).hashes()
        self.assertEqual(record["config_hashes"]["karto"], hashes["karto"])
        self.assertLessEqual(record["sim_duration_s"], self.max_sim_time + 1e-6)
        self.assertGreater(record["distance_m"], 2.0, "the robot hardly moved")
        self.assertTrue(np.isfinite(record["metric"]["trans_mean"]))
        self.assertLess(float(np.abs(traj.slam[0] - traj.odom[0]).max()), 0.05)
        self.assertGreaterEqual(len(record["snapshots"]), 1)


if __name__ == "__main__":
    rospy.init_node("test_batch_explore_karto")
    rostest.rosrun("slam_predict", "test_batch_explore_karto", BatchExploreKarto)
