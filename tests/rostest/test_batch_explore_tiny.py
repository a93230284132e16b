#!/usr/bin/env python3
"""rostest: batch_explore.launch writes a valid record of a short tiny-world exploration, in the
same format as the in-process episode (same files, same run.json keys + "ros"), and both reload."""
import dataclasses
import shutil
import subprocess
import tempfile
import time
import unittest
from pathlib import Path

import numpy as np
import rospy
import rostest

from slam_predict.collect import record as rec
from slam_predict.collect.store import run_seed
from slam_predict.ros.run_record import record_layout
from slam_predict.world.load import load_plan


def wait_for(path: Path, seconds: float) -> bool:
    """Poll (wall time) until ``path`` exists."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline and not rospy.is_shutdown():
        if path.exists():
            return True
        time.sleep(0.5)
    return path.exists()


def in_process_record(world: str, folder: Path) -> Path:
    """A short in-process episode (30 s, snapshots every 20 s) of the same world (the thesis
    explorer starts moving after 17 s: earlier snapshots would be equal and stop the run)."""
    from slam_predict.collect.batch import RunSpec
    from slam_predict.collect.episode import run_episode
    from slam_predict.collect.settings import load_settings

    settings = load_settings()
    settings.stop = dataclasses.replace(settings.stop, max_sim_time_s=30.0, interval_s=20.0,
                                        small_interval_s=20.0)
    out = folder / "tiny" / "run_000"
    run_episode(RunSpec(world, "tiny", 0, 1, str(out)), settings=settings)
    return out


class BatchExploreTiny(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.out = Path(rospy.get_param("~out"))
        cls.world = rospy.get_param("~world")
        cls.max_sim_time = float(rospy.get_param("~max_sim_time"))
        started = time.monotonic()
        cls.finished = wait_for(cls.out / "summary.csv", float(rospy.get_param("~wait")))
        cls.wall = time.monotonic() - started
        cls.run_dir = cls.out / "tiny" / "run_000"
        print(f"ROS path: batch of one {cls.max_sim_time:.0f} s tiny episode took {cls.wall:.1f} s"
              " wall (launch, run, shutdown)", flush=True)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.out, ignore_errors=True)

    def test_1_record_is_valid(self):
        self.assertTrue(self.finished, f"no summary.csv in {self.out}")
        self.assertTrue((self.run_dir / "run.json").is_file(), "the run left no record")
        record, traj = rec.load_record(self.run_dir)
        self.assertEqual((record["world"], record["run_index"]), ("tiny", 0))
        self.assertEqual(record["seed"], run_seed(0, "tiny", 0))
        self.assertIn(record["stop_reason"], ("max_sim_time", "map_converged"))
        self.assertLessEqual(record["sim_duration_s"], self.max_sim_time + 1e-6)
        # every 10 Hz sample from 0.1 s to the stop, none dropped
        n = int(round(record["sim_duration_s"] * 10))
        np.testing.assert_allclose(traj.t, np.arange(1, n + 1) * 0.1, atol=1e-6)
        self.assertEqual(record["ros"]["samples_dropped"], 0)
        # ground truth starts at the world's start pose (after one 0.1 s step at <= 1 m/s,
        # 90 deg/s) and stays in free space
        world = load_plan(self.world)
        np.testing.assert_allclose(traj.ground_truth[0], world.start_pose, atol=0.16)
        self.assertTrue(np.all(world.is_free_at(traj.ground_truth[:, :2])))
        # odometry starts at 0 (one step); SLAM's map frame starts at the first odometry pose
        np.testing.assert_allclose(traj.odom[0], 0.0, atol=0.16)
        self.assertLess(float(np.abs(traj.slam[0] - traj.odom[0]).max()), 0.05)
        # real exploration (full graph), or 0.3 m/s for 30 s (driver mode): several metres
        print(f"record: {record['distance_m']:.1f} m travelled, coverage {record['coverage']}, "
              f"stop {record['stop_reason']}", flush=True)
        self.assertGreater(record["distance_m"], 3.0, "the robot hardly moved")
        self.assertTrue(0.0 < record["coverage"] <= 1.0)
        self.assertTrue(np.isfinite(record["metric"]["trans_mean"]))
        self.assertEqual(record["odometry_error"]["model"], record["odometry_model"])
        for name in rec.FILES:
            self.assertTrue((self.run_dir / name).is_file(), name)
        snapshots = sorted((self.run_dir / "snapshots").glob("snapshot_*.png"))
        self.assertEqual(len(snapshots), len(record["snapshots"]))
        self.assertGreaterEqual(len(snapshots), 1)

    def test_2_same_format_as_the_in_process_episode(self):
        self.assertTrue((self.run_dir / "run.json").is_file(), "the run left no record")
        folder = Path(tempfile.mkdtemp(prefix="inprocess_"))
        try:
            local = in_process_record(self.world, folder)
            ros, ours = record_layout(self.run_dir), record_layout(local)
            self.assertEqual(ros["files"], ours["files"])
            self.assertEqual(sorted(set(ros["keys"]) - {"ros"}), ours["keys"])
            for key, value in ours["nested"].items():
                if key != "timing":   # wall times of each path's own phases
                    self.assertEqual(ros["nested"].get(key), value, key)
            ros_record, _ = rec.load_record(self.run_dir)
            local_record, _ = rec.load_record(local)
            for name in ("sim", "gmapping", "nav", "explore", "metric"):
                self.assertEqual(ros_record["config_hashes"][name],
                                 local_record["config_hashes"][name], name)
        finally:
            shutil.rmtree(folder, ignore_errors=True)

    def test_3_a_resume_with_another_seed_is_refused(self):
        """batch_explore on the finished campaign with base_seed 5: exit 2, the difference
        named, campaign.json and the run untouched (no run is launched)."""
        self.assertTrue((self.out / "campaign.json").is_file(), "the batch wrote no campaign.json")
        before = (self.out / "campaign.json").read_text()
        run_json = (self.run_dir / "run.json").read_text()
        result = subprocess.run(
            ["rosrun", "slam_predict", "batch_explore", "__name:=batch_explore_resume",
             f"_worlds:={self.world}", "_runs:=1", f"_out:={self.out}", "_base_seed:=5",
             "_max_sim_time:=45", "_snapshot_interval:=25"],
            capture_output=True, text=True, timeout=120)
        said = result.stdout + result.stderr
        self.assertEqual(result.returncode, 2, said)
        self.assertIn("--seed 0, not --seed 5", said)
        self.assertEqual((self.out / "campaign.json").read_text(), before)
        self.assertEqual((self.run_dir / "run.json").read_text(), run_json)


if __name__ == "__main__":
    rospy.init_node("test_batch_explore_tiny")
    rostest.rosrun("slam_predict", "test_batch_explore_tiny", BatchExploreTiny)
