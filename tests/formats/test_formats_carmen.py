"""CARMEN log reading/writing: real logs, round trips, truncated and malformed lines."""
from __future__ import annotations

import gzip
import logging
import math

import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.formats import carmen
from slam_predict.formats.carmen import CarmenLog, LaserScan, Odometry, read_log, write_log

# (FLASER lines, beams, ODOM lines) from shared/data/README.md, carmen/ table.
CORRECTED = {
    "intel": (910, 180, 14541), "aces": (440, 180, 7814), "csail": (406, 361, 2394),
    "freiburg-079": (4791, 360, 9725), "freiburg-101": (292, 360, 4569),
}
SLAM_INPUT_SCANS = {"intel": 910, "aces": 440, "csail": 406, "freiburg-079": 4791,
                    "freiburg-101": 292}


@pytest.mark.parametrize("name", sorted(CORRECTED))
def test_corrected_logs_match_readme(shared_data, name):
    n_flaser, beams, n_odom = CORRECTED[name]
    log = read_log(shared_data / "carmen" / f"{name}-corrected.log.gz")
    assert len(log.scans) == n_flaser
    assert len(log.odometry) == n_odom
    assert {len(s.ranges) for s in log.scans} == {beams}
    expected_res = math.radians(1.0 if beams in (180, 181) else 0.5)
    assert log.scans[0].angular_resolution == pytest.approx(expected_res)
    assert log.scans[0].start_angle == pytest.approx(-math.pi / 2)
    # README: in the corrected logs the odom fields equal the pose fields on every line.
    np.testing.assert_array_equal(log.scan_poses, log.scan_odom_poses)


@pytest.mark.parametrize("name", sorted(SLAM_INPUT_SCANS))
def test_slam_inputs_parse(shared_data, name):
    log = read_log(shared_data / "slam_inputs" / f"{name}.log.gz")
    n = SLAM_INPUT_SCANS[name]
    assert len(log.scans) == n and len(log.odometry) == n
    assert np.all(np.diff(log.scan_times) > 0), "timestamps strictly increasing"
    assert "robot_frontlaser_offset" in log.params
    offset = -0.04 if name.startswith("freiburg") else 0.0
    assert log.param_float("robot_frontlaser_offset") == offset
    # Reference poses and raw odometry differ (they are different trajectories).
    assert not np.allclose(log.scan_poses, log.scan_odom_poses)
    # ODOM lines carry the same odometry as the FLASER odom fields, at the same times.
    np.testing.assert_allclose(log.odometry.t, log.scan_times)
    np.testing.assert_allclose(log.odometry.poses, log.scan_odom_poses)
    assert all(s.ranges.dtype == np.float32 for s in log.scans[:5])


def test_real_log_round_trip(shared_data, tmp_path):
    log = read_log(shared_data / "slam_inputs" / "freiburg-101.log.gz")
    out = tmp_path / "copy.log.gz"
    write_log(out, log)
    again = read_log(out)
    _assert_same(log, again, range_atol=0.0)
    assert again.params == log.params


def _random_scan(rng, kind, t, n):
    return LaserScan(
        timestamp=t, ranges=rng.uniform(0.1, 30, n).astype(np.float32),
        start_angle=-math.pi / 2 if kind == "FLASER" else -2.35619449,
        angular_resolution=carmen.flaser_angular_resolution(n) if kind == "FLASER" else 0.0087,
        max_range=float("nan") if kind == "FLASER" else 60.0,
        pose=rng.normal(size=3), odom_pose=rng.normal(size=3), kind=kind,
        remissions=rng.uniform(0, 1, 4).astype(np.float32) if kind == "ROBOTLASER1" else (),
        tv=0.3, rv=-0.1, laser_type=2, accuracy=0.01, remission_mode=1)


def _random_log(seed=0):
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.05, 0.2, 12)) + 1e9
    odo = Odometry(t[::2], rng.normal(size=(6, 3)), rng.normal(size=6), rng.normal(size=6))
    scans = [_random_scan(rng, "FLASER" if i % 3 else "ROBOTLASER1", ti, 181 if i % 2 else 360)
             for i, ti in enumerate(t[1::2])]
    return CarmenLog(params={"robot_frontlaser_offset": "-0.04"}, odometry=odo, scans=scans)


def _assert_same(a, b, range_atol):
    np.testing.assert_array_equal(a.odometry.t, b.odometry.t)
    np.testing.assert_array_equal(a.odometry.poses, b.odometry.poses)
    np.testing.assert_array_equal(a.odometry.tv, b.odometry.tv)
    assert len(a.scans) == len(b.scans)
    for sa, sb in zip(a.scans, b.scans, strict=False):
        assert sa.kind == sb.kind and sa.timestamp == sb.timestamp
        np.testing.assert_allclose(sa.ranges, sb.ranges, atol=range_atol, rtol=0)
        np.testing.assert_array_equal(sa.pose, sb.pose)
        np.testing.assert_array_equal(sa.odom_pose, sb.odom_pose)
        assert sa.angular_resolution == pytest.approx(sb.angular_resolution, abs=1e-15)
        assert sa.start_angle == sb.start_angle
        np.testing.assert_array_equal(sa.remissions, sb.remissions)


@pytest.mark.parametrize("suffix", [".log", ".log.gz"])
def test_round_trip_exact_ranges(tmp_path, suffix):
    log = _random_log()
    path = tmp_path / f"run{suffix}"
    write_log(path, log, range_decimals=None, header=["made by a test"])
    again = read_log(path)
    _assert_same(log, again, range_atol=0.0)
    rl = [s for s in again.scans if s.kind == "ROBOTLASER1"][0]
    assert rl.max_range == 60.0 and rl.tv == 0.3 and rl.laser_type == 2
    assert (path.read_bytes()[:2] == b"\x1f\x8b") == suffix.endswith(".gz")


def test_round_trip_mm_ranges(tmp_path):
    log = _random_log(1)
    write_log(tmp_path / "a.log", log)
    _assert_same(log, read_log(tmp_path / "a.log"), range_atol=5e-4 + 1e-6)


def test_write_order_odom_before_scan_on_ties(tmp_path):
    log = CarmenLog(odometry=Odometry([2.0, 1.0], np.zeros((2, 3))),
                    scans=[_random_scan(np.random.default_rng(0), "FLASER", 1.0, 4)])
    write_log(tmp_path / "a.log", log)
    kinds = [ln.split()[0] for ln in (tmp_path / "a.log").read_text().splitlines()]
    assert kinds == ["ODOM", "FLASER", "ODOM"]


def test_write_trajectory_metric_evaluator_lines(tmp_path):
    t = np.array([10.5, 11.25])
    poses = np.array([[1.0, 2.0, 0.5], [1.5, -2.0, -3.0]])
    carmen.write_trajectory(tmp_path / "slam.log", t, poses)
    lines = (tmp_path / "slam.log").read_text().splitlines()
    assert lines[0] == "FLASER 0 1.0 2.0 0.5 1.0 2.0 0.5 10.5 slam_predict 10.5"
    log = read_log(tmp_path / "slam.log")
    np.testing.assert_array_equal(log.scan_poses, poses)
    np.testing.assert_array_equal(log.scan_times, t)
    assert all(len(s.ranges) == 0 for s in log.scans)


def test_flaser_resolution_from_count():
    deg = [math.degrees(carmen.flaser_angular_resolution(n)) for n in (180, 181, 360, 361)]
    assert deg == pytest.approx([1.0, 1.0, 0.5, 0.5])


def test_flaser_without_host_fields_and_comments(tmp_path):
    path = tmp_path / "a.log"
    path.write_text("# comment\nNEFF 12.5\nFLASER 2 1.0 2.0 0 0 0 1 1 1 5.0\nFOO 1 2\n"
                    "ODOM 1 2 3 0 0 0 6.0\n")
    log = read_log(path)
    assert len(log.scans) == 1 and log.scans[0].timestamp == 5.0
    assert log.scans[0].logger_timestamp is None
    np.testing.assert_array_equal(log.odometry.poses, [[1, 2, 3]])


def _two_line_log(tmp_path, last, newline=True):
    path = tmp_path / "a.log"
    path.write_text("ODOM 0 0 0 0 0 0 1.0 h 1.0\n" + last + ("\n" if newline else ""))
    return path


@pytest.mark.parametrize("last", [
    "FLASER 4 1.0 2.0 3.0 4.0 0 0 0 0 0",          # declares 4 readings, pose fields missing
    "FLASER 180 1.0 2.0",
    "ODOM 1 2 3 0 0 0 2.0 host",                    # logger timestamp missing
    "ROBOTLASER1 0 -1.57 3.14 0.01 50 0.01 0 3 1 2",
])
def test_truncated_last_line_dropped_with_warning(tmp_path, caplog, last):
    path = _two_line_log(tmp_path, last)
    with caplog.at_level(logging.WARNING, logger="slam_predict.formats.carmen"):
        log = read_log(path)
    assert len(log.scans) == 0 and len(log.odometry) == 1
    assert "truncated last line" in caplog.text and ":2:" in caplog.text


def test_unterminated_cut_number_on_last_line_dropped(tmp_path):
    path = _two_line_log(tmp_path, "FLASER 2 1.0 2.0 0 0 0 0 0 0 1.5e", newline=False)
    assert len(read_log(path).scans) == 0


@pytest.mark.parametrize("body, line, words", [
    ("FLASER 4 1.0 2.0\nODOM 0 0 0 0 0 0 1 h 1\n", 1, "too few fields"),
    ("ODOM 0 0 x 0 0 0 1 h 1\nODOM 0 0 0 0 0 0 1 h 1\n", 1, "malformed ODOM"),
    ("ODOM 0 0 0 0 0 0 1 h 1\nFLASER -3 0 0 0 0 0 0 1 h 1\n", 2, "negative"),
    ("ODOM 0 0 0 0 0 0 1 h 1 extra\n", 1, "malformed ODOM"),
    ("FLASER 1 2.0 0 0 0 0 0 0 1 h 1 7\nODOM 0 0 0 0 0 0 1 h 1\n", 1, "FLASER"),
    ("FLASER 1.5 2.0 0 0 0 0 0 0 1 h 1\n", 1, "malformed FLASER"),
])
def test_malformed_lines_raise_with_line_number(tmp_path, body, line, words):
    path = tmp_path / "bad.log"
    path.write_text(body)
    with pytest.raises(InputError) as err:
        read_log(path)
    assert err.value.line == line and err.value.path == str(path)
    assert words in err.value.one_line()


def test_missing_and_corrupt_files(tmp_path):
    with pytest.raises(InputError, match="not found"):
        read_log(tmp_path / "nope.log")
    bad = tmp_path / "bad.log.gz"
    bad.write_bytes(gzip.compress(b"ODOM 0 0 0 0 0 0 1 h 1\n")[:15])
    with pytest.raises(InputError, match="truncated gzip file"):
        read_log(bad)


def test_max_range_from_param_or_argument(tmp_path):
    path = tmp_path / "a.log"
    path.write_text("FLASER 1 2.0 0 0 0 0 0 0 1 h 1\nPARAM robot_front_laser_max 50 1.0 h 1.0\n")
    assert read_log(path).scans[0].max_range == 50.0
    assert read_log(path, max_range=30.0).scans[0].max_range == 30.0
    path.write_text("FLASER 1 2.0 0 0 0 0 0 0 1 h 1\n")
    assert math.isnan(read_log(path).scans[0].max_range)
