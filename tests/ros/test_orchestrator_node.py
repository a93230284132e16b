"""Orchestrator node plumbing without a master: tf lookups, map→odom hold, map and log callbacks,
and the run record it writes (same files and keys as the in-process episode)."""
from __future__ import annotations

import bisect
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("nav_msgs.msg", reason="ROS 1 python messages not installed")

import rospy  # noqa: E402
from rosgraph_msgs.msg import Log  # noqa: E402

from slam_predict.collect import record as rec  # noqa: E402
from slam_predict.collect.record import RunInfo  # noqa: E402
from slam_predict.collect.settings import load_settings  # noqa: E402
from slam_predict.collect.stopping import StopConfig  # noqa: E402
from slam_predict.config import to_dict  # noqa: E402
from slam_predict.geometry import compose  # noqa: E402
from slam_predict.ros.conversions.geometry import time_from_ros, time_to_ros, transform_to_ros  # noqa: E402
from slam_predict.ros.conversions.slam import grid_to_ros  # noqa: E402
from slam_predict.ros.ground_truth import GroundTruthConfig, GroundTruthSource  # noqa: E402
from slam_predict.ros.orchestrator import RunMonitor, Sample  # noqa: E402
from slam_predict.ros.orchestrator_config import OrchestratorConfig  # noqa: E402
from slam_predict.ros.orchestrator_node import OrchestratorNode  # noqa: E402
from slam_predict.ros.run_record import build_record, write_record  # noqa: E402
from slam_predict.sim.simulator import resolve_sensor  # noqa: E402
from slam_predict.slam import OccupancyGrid  # noqa: E402

ROOM = Path(__file__).resolve().parents[1] / "data" / "stage_sim_room.world"


class FakeTfBuffer:
    """Direct parent→child transforms only; exact stamps or the latest (Time(0))."""

    def __init__(self):
        self.data = {}

    def add(self, parent, child, t, pose):
        stamps, poses = self.data.setdefault((parent, child), ([], []))
        i = bisect.bisect_right(stamps, t)
        stamps.insert(i, t)
        poses.insert(i, np.asarray(pose, float))

    def _find(self, parent, child, stamp):
        stamps, poses = self.data.get((parent, child), ([], []))
        if not stamps:
            return None
        t = time_from_ros(stamp)
        if t == 0.0:
            return stamps[-1], poses[-1]
        for s, p in zip(stamps, poses, strict=False):
            if abs(s - t) < 1e-9:
                return s, p
        return None

    def can_transform(self, parent, child, stamp):
        return self._find(parent, child, stamp) is not None

    def lookup_transform(self, parent, child, stamp):
        s, p = self._find(parent, child, stamp)
        return transform_to_ros(p, s, parent, child)


class FakeRospy:
    Time = rospy.Time

    def is_shutdown(self):
        return False


def make_node(stop=None, **gt):
    monitor = RunMonitor(stop or StopConfig(max_sim_time_s=2.0), 120.0,
                         extent=(-10.0, -10.0, 10.0, 10.0))
    config = OrchestratorConfig()
    source = GroundTruthSource(GroundTruthConfig(**gt))
    tf = FakeTfBuffer()
    node = OrchestratorNode(monitor, config, source, FakeRospy(), tf)
    source.tf_pose = node.tf_pose
    return node, tf, source


def test_slam_pose_is_map_to_odom_composed_with_odometry():
    node, tf, _ = make_node()
    map_T_odom = np.array([0.2, -0.1, 0.05])
    tf.add("map", "odom", 0.1, map_T_odom)
    tf.add("odom", "base_link", 0.1, [1.0, 0.5, 0.3])
    node.ground_truth.history.add(0.1, [3.0, 3.0, 1.0])
    sample = node.lookup(0.1, 0.1)
    np.testing.assert_allclose(sample.slam, compose(map_T_odom, [1.0, 0.5, 0.3]), atol=1e-12)
    np.testing.assert_allclose(sample.odom, [1.0, 0.5, 0.3], atol=1e-12)
    np.testing.assert_allclose(sample.ground_truth, [3.0, 3.0, 1.0])


def test_map_to_odom_is_held_only_after_the_hold_time():
    node, tf, _ = make_node()
    tf.add("map", "odom", 1.0, [0.5, 0.0, 0.0])
    tf.add("odom", "base_link", 1.5, [1.0, 0.0, 0.0])
    node.ground_truth.history.add(1.5, [0.0, 0.0, 0.0])
    assert node.lookup(1.5, now=2.0) is None          # a newer map->odom may still come
    sample = node.lookup(1.5, now=2.6)                 # hold 1 s passed: keep the latest
    np.testing.assert_allclose(sample.slam, [1.5, 0.0, 0.0], atol=1e-12)
    tf.add("map", "odom", 2.0, [0.7, 0.0, 0.0])        # a later one exists: used at once
    node2, tf2, _ = make_node()
    tf2.data = tf.data
    node2.ground_truth.history.add(1.5, [0.0, 0.0, 0.0])
    assert node2.map_to_odom(1.7, now=1.7)[0] == pytest.approx(0.7)


def test_ticks_resolve_samples_and_the_run_stops():
    node, tf, _ = make_node()
    for k in range(0, 31):
        t = round(k * 0.1, 9)
        if k:
            tf.add("odom", "base_link", t, [0.1 * t, 0.0, 0.0])
            tf.add("map", "odom", t, [0.0, 0.0, 0.0])
            node.ground_truth.history.add(t, [1.0 + 0.1 * t, 2.0, 0.0])
        node.tick(t)
    assert node.monitor.reason == "max_sim_time"
    assert len(node.monitor.samples) == 20 and not node.monitor.pending
    assert node.wait_until_done() and node.drain() == 0


def test_map_and_explorer_log_callbacks():
    node, _, _ = make_node()
    grid = OccupancyGrid(np.zeros((64, 32), np.int8), 0.05, (-1.0, -2.0))
    node.on_map(grid_to_ros(grid, "map", 1.0))
    got = node.monitor.grid
    assert got.data.shape == (64, 32) and got.origin == (-1.0, -2.0) and node.maps == 1
    node.tick(12.0)
    log = Log()
    log.name, log.msg = "/move_base", "Exploration stopped."
    node.on_log(log)
    assert node.monitor.explorer_end is None
    log.name = "/explore"
    node.on_log(log)
    assert node.monitor.explorer_end == {"t": 12.0, "reason": "Exploration stopped."}


def synthetic_monitor(n=300, seed=0):
    """A finished monitor holding a noisy SLAM estimate of a loop drive, and a map."""
    rng = np.random.default_rng(seed)
    monitor = RunMonitor(StopConfig(), 120.0, extent=(-100.0, -100.0, 100.0, 100.0))
    start = np.array([-2.0, 0.0, 0.0])
    for k in range(1, n + 1):
        t = 0.1 * k
        odom = np.array([0.02 * k * np.cos(0.01 * k), 0.02 * k * np.sin(0.01 * k), 0.01 * k])
        gt = compose(start, odom)
        slam = odom + rng.normal(0.0, 0.01, 3)
        monitor.tick(t)
        monitor.resolve(lambda t_, now, gt=gt, slam=slam, odom=odom: Sample(t_, gt, slam, odom))
    data = np.full((128, 128), -1, np.int8)
    data[40:90, 30:100] = 0
    monitor.set_map(OccupancyGrid(data, 0.05, (-5.0, -3.0)))
    monitor.reason, monitor.t_stop = "max_sim_time", monitor.now
    return monitor


def test_record_has_the_episode_keys_and_reloads(tmp_path, run_record_keys):
    from slam_predict.world.load import load_plan

    settings = load_settings()
    monitor = synthetic_monitor()
    world = load_plan(ROOM)
    info = RunInfo("room", str(ROOM), 3, 42, "uniform_per_run", {"model": "uniform_per_run"},
                   {"graph": {"sim": "slam_predict"}})
    record = build_record(info, settings, monitor, world, world.free_area_m2, 12.5, {"x": 1.0})
    write_record(tmp_path, record, monitor, settings)
    assert set(record) == run_record_keys | {"ros"}
    assert record["sensor"] == to_dict(resolve_sensor(world, settings.sim))
    assert record["slam"] == {"type": "gmapping",
                              "params_hash": record["config_hashes"]["gmapping"]}
    loaded, traj = rec.load_record(tmp_path)
    assert loaded["schema"] == rec.SCHEMA_VERSION and loaded["run_index"] == 3
    assert len(traj.t) == 300 and loaded["ros"]["samples"] == 300
    for name in rec.FILES:
        assert (tmp_path / name).is_file(), name
    assert record["metric"]["trans_mean"] > 0 and record["metric"]["n"] > 0
    assert 0.0 <= record["coverage"] <= 1.0
    assert record["distance_m"] == pytest.approx(rec.path_length(traj.ground_truth))


def test_record_without_world_has_no_coverage(tmp_path):
    settings = load_settings()
    monitor = synthetic_monitor()
    record = build_record(RunInfo("lab"), settings, monitor, None, None, 1.0, {})
    assert record["coverage"] is None and record["world_file"] == "" and record["sensor"] is None
    assert record["odometry_model"] == settings.sim.odom.model
    assert time_to_ros(record["sim_duration_s"]).to_sec() == pytest.approx(30.0)
