"""Prepared scans (the differential check's input for the real openslam_gmapping) and the
driver's output format; the differential benches' refusal without an upstream checkout."""
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.formats.prepared_scans import (
    FILTER_PARAMS,
    prepared_scans_text,
    read_driver_output,
)
from slam_predict.slam import LaserGeometry
from slam_predict.slam.gmapping.params import GMappingParams, with_ranges

ROOT = Path(__file__).resolve().parents[2]


def _scans(rng, n=4, beams=5):
    angles = np.linspace(-np.pi / 2, np.pi / 2, beams) + rng.normal(0, 1e-3, beams)
    laser = LaserGeometry(np.sort(angles), (0.13, -0.02, 0.01), 30.0 + 1 / 3)
    times = 1e9 + np.cumsum(rng.uniform(0.01, 0.2, n))
    odometry = rng.normal(0, 3, (n, 3))
    ranges = rng.uniform(0, 30, (n, beams))
    return times, odometry, ranges, laser




def test_every_number_reads_back_exactly(parse_prepared):
    rng = np.random.default_rng(4)
    times, odometry, ranges, laser = _scans(rng)
    params = with_ranges(GMappingParams(particles=7, srr=0.0123456789012345), laser.range_max)
    text = prepared_scans_text(times, odometry, ranges, laser, params, 9)
    magic, header, scans = parse_prepared(text)
    assert magic == "slam_predict_prepared_scans 1"
    assert header["seed"] == ["9"] and header["angle_mode"] == ["node"]
    assert all(name in header for name in FILTER_PARAMS)
    assert header["particles"] == ["7"] and float(header["srr"][0]) == params.srr
    assert float(header["maxRange"][0]) == laser.range_max - 0.01 == float(header["maxUrange"][0])
    assert [float(v) for v in header["laser_pose"]] == list(laser.pose_in_base)
    assert int(header["angles"][0]) == 5
    np.testing.assert_array_equal([float(v) for v in header["angles"][1:]], laser.angles)
    np.testing.assert_array_equal(scans[:, 0], times)
    np.testing.assert_array_equal(scans[:, 1:4], odometry)
    np.testing.assert_array_equal(scans[:, 4:], ranges)


def test_bad_inputs_are_refused():
    rng = np.random.default_rng(5)
    times, odometry, ranges, laser = _scans(rng)
    params = with_ranges(GMappingParams(), laser.range_max)
    with pytest.raises(ValueError, match="resolved"):
        prepared_scans_text(times, odometry, ranges, laser, GMappingParams(), 1)
    with pytest.raises(ValueError, match="angle_mode"):
        prepared_scans_text(times, odometry, ranges, laser, params, 1, angle_mode="ros")
    with pytest.raises(ValueError, match="beams"):
        prepared_scans_text(times, odometry, ranges[:, :3], laser, params, 1)


def test_driver_output_is_read(tmp_path):
    path = tmp_path / "real.traj"
    path.write_text("# scan_index time x y theta (robot pose, map frame)\n"
                    "0 10.5 0.0 0.0 0.0\n3 11.25 1.5 -0.25 0.125\n"
                    "# neff 29.5\n# neff 12.25\n# summary processed 2 resamples 1 best 4\n")
    out = read_driver_output(path)
    np.testing.assert_array_equal(out.indices, [0, 3])
    np.testing.assert_array_equal(out.times, [10.5, 11.25])
    np.testing.assert_array_equal(out.poses, [[0, 0, 0], [1.5, -0.25, 0.125]])
    assert out.neff == [29.5, 12.25] and out.resamples == 1 and out.best == 4


@pytest.mark.parametrize("text, message", [
    ("0 1.0 0 0 0\n", "no summary"),
    ("0 1.0 0 0 0\n# summary processed 2 resamples 0 best 0\n", "summary says 2"),
    ("0 1.0 0 0\n# summary processed 1 resamples 0 best 0\n", "line 1"),
])
def test_incomplete_driver_output_is_an_input_error(tmp_path, text, message):
    path = tmp_path / "real.traj"
    path.write_text(text)
    with pytest.raises(InputError, match=message):
        read_driver_output(path)


@pytest.mark.parametrize("script, variable, library", [
    ("bench_gmapping_diff.py", "SLAM_PREDICT_GMAPPING_UPSTREAM", "openslam_gmapping"),
    ("bench_karto_diff.py", "SLAM_PREDICT_KARTO_UPSTREAM", "slam_toolbox"),
])
def test_bench_without_upstream_says_how_to_get_it(script, variable, library):
    env = {k: v for k, v in os.environ.items() if k != variable}
    proc = subprocess.run([sys.executable, str(ROOT / "bench" / script)],
                          env=env, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    assert library in proc.stderr and "--upstream" in proc.stderr
