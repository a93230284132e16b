"""Sensor logs of a collected run: sensors.bag / sensors.log.gz hold every scan and step, and
replaying either through our GMapping gives the in-loop SLAM trajectory exactly."""
import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

from slam_predict.cli.main import main
from slam_predict.collect.batch import RunSpec
from slam_predict.collect.episode import run_episode
from slam_predict.collect.record import without_timing
from slam_predict.collect.sensorlog import SENSOR_BAG, SENSOR_LOG, SLAM_SCANS
from slam_predict.collect.settings import load_settings
from slam_predict.formats.carmen import read_log
from slam_predict.formats.tum import read_tum

ROOT = Path(__file__).resolve().parents[2]
TINY = ROOT / "worlds" / "tiny.world"
SIM_TIME = 20.0


def settings(sensor_logs: bool, **slam_params):
    s = load_settings()
    s.slam.params = dataclasses.replace(s.slam.params, particles=6, **slam_params)
    s.stop = dataclasses.replace(s.stop, max_sim_time_s=SIM_TIME, small_interval_s=30.0)
    s.sensor_logs = sensor_logs
    return s


def collect(folder: Path, sensor_logs: bool, **slam_params) -> dict:
    spec = RunSpec(str(TINY), "tiny", 0, 5, str(folder))
    return run_episode(spec, settings(sensor_logs, **slam_params))


@pytest.fixture(scope="module")
def collected(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sensorlogs") / "tiny" / "run_000"
    return collect(folder, True), folder


def tum_rows(path: Path):
    return [line for line in path.read_text().splitlines() if not line.startswith("#")]


@pytest.mark.parametrize("name", [SENSOR_BAG, SENSOR_LOG])
def test_replay_equals_the_in_loop_slam_trajectory_exactly(collected, tmp_path, capsys, name):
    record, folder = collected
    out = tmp_path / "replay"
    assert main(["slam", "run", str(folder / name), "--out", str(out)]) == 0
    replayed, in_loop = tum_rows(out / "slam.tum"), tum_rows(folder / SLAM_SCANS)
    assert len(in_loop) == record["sensor_logs"]["slam_scans"] > 5
    assert replayed == in_loop  # same count, same poses and times to the last bit
    stats = json.loads((out / "stats.json").read_text())
    assert stats["seed"] == record["seed"] and "in-loop SLAM generator" in stats["rng"]
    assert stats["params"] == record["sensor_logs"]["gmapping"]
    assert stats["scans_seen"] == record["sensor_logs"]["scans"]
    assert stats["evaluation"]["slam"]["trans_mean_m"] < 0.2  # ground truth is the reference
    assert stats["random_stream"] == record["sensor_logs"]["gmapping"]["random_stream"] \
        == "drand48" and 1 <= stats["drand48_seed"] < 2 ** 31 - 1


def test_a_run_recorded_before_random_stream_replays_on_numpy(tmp_path):
    """A run.json without ``random_stream`` (written before the option existed, when the numpy
    stream was the only one) replays on numpy, reproducing its in-loop trajectory exactly."""
    folder = tmp_path / "tiny" / "run_000"
    record = collect(folder, True, random_stream="numpy")
    recorded = record["sensor_logs"]["gmapping"]
    assert recorded.pop("random_stream") == "numpy" and recorded.pop("drand48_seed") is None
    (folder / "run.json").write_text(json.dumps(record))
    out = tmp_path / "replay"
    assert main(["slam", "run", str(folder / SENSOR_BAG), "--out", str(out)]) == 0
    assert tum_rows(out / "slam.tum") == tum_rows(folder / SLAM_SCANS)
    assert json.loads((out / "stats.json").read_text())["random_stream"] == "numpy"


def test_replay_applies_the_runs_compute_delay(tmp_path, capsys):
    """A run collected with slam_gmapping's compute delay (scans dropped while GMapping is
    busy) replays exactly: `slam run` hands GMapping the same scans from run.json's model."""
    from slam_predict.slam.compute_delay import ComputeDelayConfig

    s = settings(True)
    s.compute = ComputeDelayConfig(model="cost", scan_s=0.35, rebuild_s_per_map_cell=2e-8)
    folder = tmp_path / "tiny" / "run_000"
    record = run_episode(RunSpec(str(TINY), "tiny", 0, 5, str(folder)), s)
    assert record["slam_compute"]["scans_dropped"] > 0
    assert record["slam_compute"]["scan_s"] == 0.35 and "slam_compute" in record["config_hashes"]
    out = tmp_path / "replay"
    assert main(["slam", "run", str(folder / SENSOR_BAG), "--out", str(out)]) == 0
    replayed, in_loop = tum_rows(out / "slam.tum"), tum_rows(folder / SLAM_SCANS)
    assert len(in_loop) > 5 and replayed == in_loop
    stats = json.loads((out / "stats.json").read_text())
    assert stats["slam_compute"]["scans_dropped"] == record["slam_compute"]["scans_dropped"]
    check_handed_scans_alone_give_the_in_loop_trajectory(folder, record)


def check_handed_scans_alone_give_the_in_loop_trajectory(folder: Path, record: dict):
    """The scans the delay handed GMapping, fed without a delay, give the in-loop trajectory
    (what the differential check feeds both GMappings of a delayed run)."""
    from slam_predict.slam import runner

    setup = runner.recorded_run(folder / SENSOR_BAG)
    data = runner.read_input(folder / SENSOR_BAG)
    delayed = runner.run(data, setup.slam_type, setup.params, setup.seed, rng=setup.rng(),
                         compute=setup.compute)
    assert len(delayed.handed) == record["slam_compute"]["scans_handled"] < len(data)
    lockstep = runner.run(data.take(delayed.handed), setup.slam_type, setup.params, setup.seed,
                          rng=setup.rng())
    assert lockstep.handed is None
    assert np.array_equal(lockstep.poses, delayed.poses)
    assert np.array_equal(lockstep.times, delayed.times)


def test_replay_with_another_seed_differs(collected, tmp_path):
    _, folder = collected
    out = tmp_path / "replay"
    assert main(["slam", "run", str(folder / SENSOR_BAG), "--seed", "1", "--out", str(out)]) == 0
    assert tum_rows(out / "slam.tum") != tum_rows(folder / SLAM_SCANS)


def test_bag_holds_the_stage_ros_stream(collected):
    from rosbags.highlevel import AnyReader

    record, folder = collected
    steps = record["sensor_logs"]["steps"]
    assert steps == round(record["sim_duration_s"] / 0.1) == record["sensor_logs"]["scans"]
    with AnyReader([folder / SENSOR_BAG]) as reader:
        counts = {c.topic: (c.msgtype, c.msgcount) for c in reader.connections}
        assert counts == {"/tf": ("tf2_msgs/msg/TFMessage", steps),
                          "/odom": ("nav_msgs/msg/Odometry", steps),
                          "/base_pose_ground_truth": ("nav_msgs/msg/Odometry", steps),
                          "/base_scan": ("sensor_msgs/msg/LaserScan", steps)}
        msgs = {}
        for conn, _, raw in reader.messages():
            msgs.setdefault(conn.topic, []).append(reader.deserialize(raw, conn.msgtype))
    scan = msgs["/base_scan"][0]
    fov = 4.712389
    assert scan.header.frame_id == "base_laser_link" and len(scan.ranges) == 541
    assert scan.angle_min == np.float32(-fov / 2) and scan.angle_increment == np.float32(fov / 540)
    assert scan.range_max == 80.0 and scan.range_min == 0.0 and scan.time_increment == 0.0
    assert np.array_equal(scan.intensities, (scan.ranges < 80.0).astype(np.float32))
    links = [(tr.header.frame_id, tr.child_frame_id) for tr in msgs["/tf"][0].transforms]
    assert links == [("odom", "base_footprint"), ("base_footprint", "base_link"),
                     ("base_link", "base_laser_link")]
    stamps = [m.header.stamp.sec + m.header.stamp.nanosec * 1e-9 for m in msgs["/odom"]]
    assert np.allclose(stamps, 0.1 * np.arange(1, steps + 1), atol=1e-9, rtol=0)
    t_gt, gt = read_tum(folder / "ground_truth.tum")
    truth = np.array([[m.pose.pose.position.x, m.pose.pose.position.y]
                      for m in msgs["/base_pose_ground_truth"]])
    assert np.array_equal(truth, gt[:, :2])
    assert msgs["/odom"][0].child_frame_id == "base_footprint"


def test_carmen_log_holds_every_scan_and_step(collected):
    record, folder = collected
    log = read_log(folder / SENSOR_LOG)
    steps = record["sensor_logs"]["steps"]
    assert len(log.scans) == record["sensor_logs"]["scans"] == steps
    assert len(log.odometry) == steps
    scan = log.scans[0]
    assert scan.kind == "ROBOTLASER1" and len(scan.ranges) == 541
    assert scan.max_range == 80.0 and math.isclose(scan.start_angle, -4.712389 / 2, abs_tol=1e-6)
    assert log.params["robot_frontlaser_offset"] == "0.0"
    _, gt = read_tum(folder / "ground_truth.tum")
    assert np.array_equal(log.scan_poses[:, :2], gt[:, :2])  # reference = ground truth
    _, odom = read_tum(folder / "odom.tum")
    assert np.array_equal(log.scan_odom_poses[:, :2], odom[:, :2])
    assert np.allclose(log.scan_odom_poses[:, 2], odom[:, 2], atol=1e-12, rtol=0)
    assert np.array_equal(log.odometry.poses, log.scan_odom_poses)


def test_no_temporary_files_are_left(collected):
    _, folder = collected
    assert not [p.name for p in folder.iterdir() if p.name.startswith(".")]


def test_logs_do_not_change_the_run_and_are_off_by_default(collected, tmp_path):
    record, folder = collected
    assert load_settings().sensor_logs is False
    plain = collect(tmp_path / "plain", False)
    assert not (tmp_path / "plain" / SENSOR_BAG).exists()
    assert "sensor_logs" not in plain
    logged = {k: v for k, v in without_timing(record).items() if k != "sensor_logs"}
    assert logged == without_timing(plain)
    assert (tmp_path / "plain" / "slam.tum").read_text() == (folder / "slam.tum").read_text()


def test_debian_rosbag_reads_the_bag(collected):
    rosbag = pytest.importorskip("rosbag", reason="python3-rosbag (Debian) not installed")
    record, folder = collected
    with rosbag.Bag(str(folder / SENSOR_BAG)) as bag:
        info = bag.get_type_and_topic_info()
        assert info.topics["/base_scan"].msg_type == "sensor_msgs/LaserScan"
        assert info.topics["/base_scan"].message_count == record["sensor_logs"]["scans"]
        assert info.msg_types["sensor_msgs/LaserScan"] == "90c7ef2dc6895d81024acba2ac42f369"
        assert info.msg_types["tf2_msgs/TFMessage"] == "94810edda583a504dfda3829e70d7eec"
        _, msg, t = next(bag.read_messages(topics=["/base_scan"]))
        assert msg.header.stamp == t and len(msg.ranges) == 541
