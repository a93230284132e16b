"""TUM trajectory files: exact round trip, planar projection, bad lines."""
from __future__ import annotations

import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.formats.tum import read_tum, write_tum
from slam_predict.geometry import wrap_angle


def test_round_trip_full_precision(tmp_path):
    rng = np.random.default_rng(3)
    t = 1.6e9 + np.cumsum(rng.uniform(0.001, 0.1, 200))
    poses = np.column_stack([rng.normal(0, 50, 200), rng.normal(0, 50, 200),
                             rng.uniform(-np.pi, np.pi, 200)])
    write_tum(tmp_path / "a.tum", t, poses, header=["test"])
    t2, p2 = read_tum(tmp_path / "a.tum")
    np.testing.assert_array_equal(t2, t)
    np.testing.assert_array_equal(p2[:, :2], poses[:, :2])
    np.testing.assert_allclose(wrap_angle(p2[:, 2] - poses[:, 2]), 0, atol=1e-14)


def test_line_layout(tmp_path):
    write_tum(tmp_path / "a.tum", [1.5], [[2.0, 3.0, np.pi / 2]])
    values = [float(v) for v in (tmp_path / "a.tum").read_text().split()]
    assert values[:4] == [1.5, 2.0, 3.0, 0.0]
    np.testing.assert_allclose(values[4:], [0, 0, np.sqrt(0.5), np.sqrt(0.5)], atol=1e-15)


def test_reads_3d_pose_as_yaw(tmp_path):
    (tmp_path / "a.tum").write_text("# c\n\n1 1 2 5 0 0 0.3826834323650898 0.9238795325112867\n")
    t, poses, z = read_tum(tmp_path / "a.tum", return_z=True)
    np.testing.assert_allclose(poses, [[1, 2, np.pi / 4]])
    assert z.tolist() == [5.0]


@pytest.mark.parametrize("text, words", [
    ("1 2 3 4 5 6 7\n", "expected 8 values"),
    ("1 2 3 4 x 0 0 1\n", "non-numeric"),
    ("1 2 3 nan 0 0 0 1\n", "non-finite"),
    ("1 2 3 0 0 0 0 2\n", "quaternion norm"),
])
def test_bad_lines(tmp_path, text, words):
    (tmp_path / "a.tum").write_text("0 0 0 0 0 0 0 1\n" + text + "3 0 0 0 0 0 0 1\n")
    with pytest.raises(InputError, match=words) as err:
        read_tum(tmp_path / "a.tum")
    assert str(tmp_path / "a.tum") in err.value.one_line()


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match="not found"):
        read_tum(tmp_path / "none.tum")


@pytest.mark.parametrize("last", ["2 1 2 0 0 0\n", "2 1 2 0 0 0 0 1."])
def test_truncated_last_line_dropped(tmp_path, caplog, last):
    (tmp_path / "a.tum").write_text("1 0 0 0 0 0 0 1\n" + last.replace("1.", "1e"))
    t, poses = read_tum(tmp_path / "a.tum")
    assert t.tolist() == [1.0] and "truncated last line" in caplog.text
