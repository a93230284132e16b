"""`slam-predict slam run`: outputs on a real-log slice, one-line errors with exit code 2."""
import json

import numpy as np
import pytest
import yaml

from slam_predict.cli.main import main
from slam_predict.formats.tum import read_tum


def test_run_writes_trajectory_map_and_stats(shared_dir, tmp_path):
    log = shared_dir / "data" / "slam_inputs" / "freiburg-101.log.gz"
    cfg = shared_dir / "baselines" / "gmapping_real_freiburg-101.yaml"
    out = tmp_path / "run"
    assert main(["slam", "run", str(log), "--config", str(cfg), "--seed", "2", "--out", str(out),
                 "--max-scans", "30"]) == 0
    stats = json.loads((out / "stats.json").read_text())
    t, poses = read_tum(out / "slam.tum")
    assert stats["scans_processed"] == len(t) == len(poses) > 5
    assert stats["input_info"]["laser_offset_m"] == -0.04
    assert stats["seed"] == 2 and stats["params"]["particles"] == 30
    assert np.all(np.diff(t) > 0)
    meta = yaml.safe_load((out / "map.yaml").read_text())
    assert meta["image"] == "map.pgm" and meta["resolution"] == 0.05
    assert (out / "map.pgm").stat().st_size > 1000 and (out / "map.png").exists()
    assert (out / "slam.log").read_text().count("FLASER") == len(t)
    evaluation = stats["evaluation"]
    assert evaluation["slam"]["trans_mean_m"] < evaluation["odometry"]["trans_mean_m"]


@pytest.mark.parametrize("make, message", [
    (lambda d: ["slam", "run", str(d / "missing.log"), "--out", str(d / "o")], "not found"),
    (lambda d: ["slam", "run", str(d / "empty.log"), "--out", str(d / "o")], "no FLASER"),
    (lambda d: ["slam", "run", str(d / "x.bag"), "--out", str(d / "o")], "cannot open ROS bag"),
    (lambda d: ["slam", "run", str(d / "empty.log"), "--config", str(d / "bad.yaml"),
                "--out", str(d / "o")], "did you mean 'particles'"),
    (lambda d: ["slam", "run", str(d / "bad.log"), "--out", str(d / "o")], "bad.log:2"),
])
def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys, make, message):
    (tmp_path / "empty.log").write_text("PARAM robot_frontlaser_offset 0.0 nohost 0\n")
    (tmp_path / "bad.yaml").write_text("particle: 3\n")
    (tmp_path / "x.bag").write_bytes(b"")
    (tmp_path / "bad.log").write_text("ODOM 0 0 0 0 0 0 1.0 h 1.0\nFLASER 2 1.0 x 0 0 0 0 0 0 2.0"
                                      " h 2.0\nODOM 0 0 0 0 0 0 3.0 h 3.0\n")
    assert main(make(tmp_path)) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "\n" not in err and err.startswith("slam-predict slam: error:")
    assert not (tmp_path / "o").exists()
