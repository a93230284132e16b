"""The report shows each campaign's robots and SLAM back-ends (from run.json), names the spread
over runs and the spread over a run's relations differently, and writes n/a where a building
has one run (no spread over runs), never a 0 that reads as a measured value."""
from __future__ import annotations

import json
import math
import shutil

from slam_predict.collect.summary import write_summary
from slam_predict.report.build import build_report

LDS = {"laser": {"range_max": 3.5, "fov": 2 * math.pi, "samples": 360},
       "odom": {"model": "fixed", "error": [0.01, 0.01, math.radians(2.0)]}}


def with_robot(campaign_dir, tmp_path):
    """The fake campaign, its runs recorded with the LDS robot and our GMapping; beta keeps
    one run."""
    data = shutil.copytree(campaign_dir, tmp_path / "data")
    for path in data.glob("*/run_*/run.json"):
        record = json.loads(path.read_text())
        record.update(sensor=LDS, slam={"type": "gmapping", "params_hash": "x"})
        path.write_text(json.dumps(record))
    shutil.rmtree(data / "beta" / "run_001")
    write_summary(data)
    return data


def test_robot_backend_spreads_and_one_run(campaign_dir, tmp_path, parse):
    page = parse(build_report(with_robot(campaign_dir, tmp_path)))
    robot = "laser 3.5 m, 360°, 360 beams; odometry fixed 0.01, 0.01 m/m, 2 °/rad"
    html = build_report(with_robot(campaign_dir, tmp_path / "again"))
    assert f"{robot} (4 runs)" in html                 # overview: the campaign's robots
    assert "gmapping (4 runs)" in html                 # and SLAM back-ends
    assert f"{robot} (3 runs)" in html and f"{robot} (1 runs)" in html   # per world
    summary = page.rows_by_first(page.table(["world", "runs"], section="Per-building summary"))
    assert summary["beta"]["std of trans_mean over runs [m]"] == "n/a (1 run)"
    assert summary["beta"]["std of rot_mean over runs [rad]"] == "n/a (1 run)"
    assert summary["alpha"]["std of trans_mean over runs [m]"] not in ("n/a (1 run)", "")
    runs = page.table(["run", "seed"], section="World alpha")
    assert "std over relations [m]" in runs["header"] and "trans_std [m]" not in runs["header"]
