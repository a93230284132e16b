"""Karto prepared scans (the differential check's input for the real Karto SDK), the driver's
JSON output, and the bench's pose agreement."""
import json

import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.formats.karto_scans import karto_scans_text, read_karto_driver_output
from slam_predict.slam import LaserGeometry


def _scans(rng, n=4, beams=7, range_max=30.0 + 1 / 3):
    angles = -np.pi / 2 + np.arange(beams) * (np.pi / (beams - 1))
    laser = LaserGeometry(angles, (0.13, -0.02, 0.01), range_max)
    times = 1e9 + np.cumsum(rng.uniform(0.01, 0.2, n))
    odometry = rng.normal(0, 3, (n, 3))
    ranges = rng.uniform(0, 30, (n, beams))
    return times, odometry, ranges, laser




def test_every_number_reads_back_exactly(parse_prepared):
    times, odometry, ranges, laser = _scans(np.random.default_rng(4))
    text = karto_scans_text(times, odometry, ranges, laser, 0.125)
    magic, header, scans = parse_prepared(text)
    assert magic == "slam_predict_prepared_scans 1" and header["backend"] == ["karto"]
    assert [float(v) for v in header["laser_pose"]] == list(laser.pose_in_base)
    assert int(header["angles"][0]) == 7
    np.testing.assert_array_equal([float(v) for v in header["angles"][1:]], laser.angles)
    assert float(header["range_min"][0]) == 0.125
    assert float(header["range_max"][0]) == laser.range_max
    np.testing.assert_array_equal(scans[:, 0], times)
    np.testing.assert_array_equal(scans[:, 1:4], odometry)
    np.testing.assert_array_equal(scans[:, 4:], ranges)


def test_unknown_range_max_is_the_longest_reading(parse_prepared):
    times, odometry, ranges, laser = _scans(np.random.default_rng(6), range_max=float("nan"))
    _, header, _ = parse_prepared(karto_scans_text(times, odometry, ranges, laser))
    assert float(header["range_max"][0]) == ranges.max()


def test_bad_inputs_are_refused():
    times, odometry, ranges, laser = _scans(np.random.default_rng(5))
    with pytest.raises(ValueError, match="beams"):
        karto_scans_text(times, odometry, ranges[:, :3], laser)
    with pytest.raises(ValueError, match="length"):
        karto_scans_text(times, odometry[:2], ranges, laser)
    uneven = LaserGeometry(laser.angles + np.r_[0.0, 1e-3, np.zeros(5)], laser.pose_in_base,
                           laser.range_max)
    with pytest.raises(ValueError, match="evenly spaced"):
        karto_scans_text(times, odometry, ranges, uneven)


def _record(**changes):
    record = {"format": "karto_driver 1", "gate": "sync", "threads": 1, "scans_in": 9,
              "cpu_total_s": 0.5,
              "accepted": [[0, 10.5, 0, 0, 0], [3, 11.25, 1.5, -0.25, 0.125]],
              "loop_closures": [[3, 0]], "process_cpu_s": [[0, 0.01], [3, 0.02], [5, 0.001]],
              "grid_cpu": [{"after_input": 8, "accepted": 2, "cells": 100, "resolution": 0.05,
                            "cpu_s": 0.003}]}
    record.update(changes)
    return json.dumps(record)


def test_driver_output_is_read(tmp_path):
    path = tmp_path / "real.json"
    path.write_text(_record())
    out = read_karto_driver_output(path)
    np.testing.assert_array_equal(out.indices, [0, 3])
    np.testing.assert_array_equal(out.stamps, [10.5, 11.25])
    np.testing.assert_array_equal(out.poses, [[0, 0, 0], [1.5, -0.25, 0.125]])
    np.testing.assert_array_equal(out.loop_closures, [[3, 0]])
    np.testing.assert_array_equal(out.process_cpu[:, 0], [0, 3, 5])
    assert out.grid_cpu[0]["cells"] == 100 and out.scans_in == 9 and out.cpu_total_s == 0.5


@pytest.mark.parametrize("text, message", [
    ("{", "not a Karto driver output"),
    (_record(format="gmapping"), "format"),
    (_record(accepted=[[0, 1.0, 0, 0]]), "not a Karto driver output"),
])
def test_broken_driver_output_is_an_input_error(tmp_path, text, message):
    path = tmp_path / "real.json"
    path.write_text(text)
    with pytest.raises(InputError, match=message):
        read_karto_driver_output(path)


def test_pose_agreement_counts_real_scans_ours_matched_within_1_cm(load_bench):
    bench = load_bench("bench_karto_diff")
    real = {"indices": [0, 4, 7, 9], "poses": [[0, 0, 0], [1, 1, 0], [2, 0, 0], [3, 0, 0]]}
    ours = {"indices": [0, 4, 9, 11],
            "poses": [[0.009, 0, 0], [1, 1.011, 0], [3, 0, 1.0], [5, 0, 0]]}
    # scan 0 within 9 mm, 4 off by 11 mm, 7 not accepted by ours, 9 same position
    assert bench.within_tolerance(ours, real) == pytest.approx(0.5)

