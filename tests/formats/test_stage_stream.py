"""stage_ros' stream without ROS: stamps, float32 LaserScan fields, the streamed bag and CARMEN
writers, and the live decoding that must equal reading the bag back."""
import gzip
import math
from types import SimpleNamespace

import numpy as np
import pytest

from slam_predict.formats.carmen import CarmenLogWriter, read_log, scan_line
from slam_predict.formats.carmen_records import LaserScan
from slam_predict.formats.sensor_bag import SensorBagWriter
from slam_predict.formats.stage_stream import (
    LaserDescription,
    StagePublisher,
    ros_time,
    stamp_seconds,
)
from slam_predict.slam.bag_input import LiveDecoder, TfTree, read_bag_input

SPEC = SimpleNamespace(fov=math.radians(270.0), samples=541, range_min=0.1, range_max=5.6)


def state(t, true_pose, odom_pose, velocity=(0.4, 0.2), scan=None):
    return SimpleNamespace(t=t, true_pose=np.array(true_pose, float),
                           odom_pose=np.array(odom_pose, float), velocity=velocity, scan=scan)


def test_ros_time_rounds_to_the_nanosecond():
    assert ros_time(0.1 * 3) == (0, 300_000_000)
    assert ros_time(1.9999999999) == (2, 0)
    assert ros_time(12.5) == (12, 500_000_000)
    assert math.isclose(stamp_seconds(*ros_time(0.7)), 0.7, abs_tol=1e-15)  # not always equal


def test_laser_description_is_float32_exact():
    d = LaserDescription.of(SPEC, (0.1, -0.05, 0.3))
    for value, exact in ((d.angle_min, -SPEC.fov / 2), (d.angle_increment, SPEC.fov / 540),
                         (d.range_max, 5.6), (d.range_min, 0.1)):
        assert value == float(np.float32(exact)) and value != exact
    assert d.mount.translation == (0.1, -0.05, 0.0)
    assert np.allclose(d.mount.rotation, (0, 0, math.sin(0.15), math.cos(0.15)))
    assert np.array_equal(d.intensities(np.float32([1.0, 5.6, 2.0])), [1.0, 0.0, 1.0])


def test_ground_truth_twist_is_the_finite_difference_over_the_step():
    pub = StagePublisher(LaserDescription.of(SPEC, (0, 0, 0)), 0.1, (1.0, 2.0, 3.1))
    msgs = pub.messages(state(0.1, (1.02, 2.01, -3.1), (0.02, 0.0, 0.05)))
    assert np.allclose(msgs.true_twist, (0.2, 0.1, (2 * math.pi - 6.2) / 0.1))
    assert msgs.odom_twist == (0.4, 0.0, 0.2) and msgs.ranges is None
    msgs = pub.messages(state(0.2, (1.02, 2.01, -3.1), (0.02, 0.0, 0.05)))
    assert np.allclose(msgs.true_twist, 0.0)


def stream(n=40, mount=(0.12, 0.03, 0.2), seed=0):
    """Steps of a robot driving an arc with random ranges (some below range_min)."""
    rng = np.random.default_rng(seed)
    laser = LaserDescription.of(SPEC, mount)
    pub = StagePublisher(laser, 0.1, (0.0, 0.0, 0.0))
    steps = []
    for k in range(1, n + 1):
        yaw = 0.37 * k
        ranges = rng.uniform(0.0, 5.6, 541).astype(np.float32) if k % 2 else None
        steps.append(pub.messages(state(0.1 * k, (0.1 * k, 0.01 * k, yaw),
                                        (0.1 * k, 0.02 * k, math.remainder(yaw, 2 * math.pi)),
                                        scan=ranges)))
    return laser, steps


def test_live_decoding_equals_reading_the_bag_back(tmp_path):
    laser, steps = stream()
    writer = SensorBagWriter(tmp_path / "s.bag", laser)
    for msgs in steps:
        writer.write(msgs)
    writer.close()
    data = read_bag_input(tmp_path / "s.bag")
    decoder = LiveDecoder(laser)
    live = [decoder.scan(m) for m in steps if m.ranges is not None]
    assert len(data) == len(live) == 20
    assert np.array_equal(data.times, [t for _, _, t in live])
    assert np.array_equal(data.odometry, [pose for pose, _, _ in live])
    assert np.array_equal(data.ranges, [r for _, r, _ in live])
    assert np.array_equal(data.laser.angles, decoder.laser.angles)
    assert data.laser.pose_in_base == decoder.laser.pose_in_base == (0.12, 0.03, 0.0)
    # against the obvious: the poses and beams that were published
    scans = [m for m in steps if m.ranges is not None]
    assert np.allclose(data.odometry, [m.odom_pose for m in scans], atol=1e-12, rtol=0)
    first, step = float(np.float32(-SPEC.fov / 2)), float(np.float32(SPEC.fov / 540))
    assert np.allclose(data.laser.angles, 0.2 + first + step * np.arange(541), atol=1e-12,
                       rtol=0)
    low = scans[0].ranges < np.float32(0.1)
    assert low.any() and np.all(data.ranges[0][low] == np.float32(5.6))
    assert np.array_equal(data.ranges[0][~low], scans[0].ranges[~low])
    truth = np.array([m.true_pose for m in scans])
    truth[:, 2] = np.remainder(truth[:, 2] + math.pi, 2 * math.pi) - math.pi
    assert np.allclose(data.reference, truth, atol=1e-12, rtol=0)


def test_tf_lookup_returns_a_sample_unchanged_at_its_stamp_and_interpolates_between():
    tree = TfTree()
    a = np.array([0.0, 0.0, 0.0, 0.0, 0.0, math.sin(0.1), math.cos(0.1)])
    b = np.array([1.0, 2.0, 0.0, 0.0, 0.0, math.sin(0.3), math.cos(0.3)])
    tree.add("odom", "base", 1.0, a, static=False)
    tree.add("odom", "base", 2.0, b, static=False)
    assert tree._link("base", 2.0) is b
    mid = tree._link("base", 1.5)
    assert np.allclose(mid[:3], [0.5, 1.0, 0.0])
    assert math.isclose(2 * math.atan2(mid[5], mid[6]), 0.4, abs_tol=1e-3)
    assert tree._link("base", 2.5) is None


def test_carmen_writer_streams_atomically(tmp_path):
    path = tmp_path / "x.log.gz"
    writer = CarmenLogWriter(path, header=["hello"])
    scan = LaserScan(timestamp=0.30000000000000004, ranges=np.float32([1.1, 2.25, 3.0e-3]),
                     start_angle=-1.0, angular_resolution=0.5, max_range=5.6,
                     pose=(1, 2, 0.5), odom_pose=(0.1, 0.2, 0.3), kind="ROBOTLASER1")
    writer.write(scan_line(scan, range_decimals=None))
    assert not path.exists() and len(list(tmp_path.iterdir())) == 1
    writer.close()
    assert [p.name for p in tmp_path.iterdir()] == ["x.log.gz"]
    text = gzip.open(path, "rt").read()
    assert text.startswith("# hello\nROBOTLASER1 ") and " 1.10000002 2.25 0.00300000003 " in text
    back = read_log(path).scans[0]
    assert np.array_equal(back.ranges, scan.ranges) and back.timestamp == scan.timestamp
    assert np.array_equal(back.angles, scan.angles)
    aborted = CarmenLogWriter(tmp_path / "y.log")
    aborted.write("ODOM 0 0 0 0 0 0 1 h 1")
    aborted.abort()
    assert [p.name for p in tmp_path.iterdir()] == ["x.log.gz"]


def test_bag_writer_abort_leaves_nothing(tmp_path):
    laser, steps = stream(n=3)
    writer = SensorBagWriter(tmp_path / "s.bag", laser)
    writer.write(steps[0])
    writer.abort()
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("value", [np.float32(0.1), np.float32(1 / 3), np.float32(79.99999),
                                   np.float32(1e-7), np.float32(12345.678)])
def test_float32_range_text_reads_back_exactly(value):
    scan = LaserScan(0.0, np.float32([value]), 0.0, 0.1, 80.0, (0, 0, 0), (0, 0, 0))
    token = scan_line(scan, range_decimals=None).split()[2]
    assert np.float32(token) == value and np.float32(float(token)) == value and len(token) <= 15
