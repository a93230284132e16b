"""``slam-predict metric``: TUM / CARMEN / bag inputs give the same numbers; bad input → exit 2."""
from __future__ import annotations

import json

import numpy as np
import pytest
from metric_trajgen import perturbed, random_walk

from slam_predict.cli.main import main
from slam_predict.formats import carmen
from slam_predict.formats.rosbag import write_pose_bag
from slam_predict.formats.tum import write_tum
from slam_predict.metric import evaluate_against_reference


@pytest.fixture
def recorded(tmp_path):
    """A ground truth and a SLAM estimate at 10 Hz, as TUM, CARMEN and bag files."""
    rng = np.random.default_rng(4)
    ref = random_walk(rng, 400)
    est = perturbed(rng, ref, sigma=(0.01, 0.01, 0.003))
    t = 1000.0 + 0.1 * np.arange(400)
    write_tum(tmp_path / "gt.tum", t, ref)
    write_tum(tmp_path / "slam.tum", t, est)
    carmen.write_trajectory(tmp_path / "gt.log", t, ref)
    carmen.write_trajectory(tmp_path / "slam.log.gz", t, est)
    write_pose_bag(tmp_path / "run.bag", {"/ground_truth": (t, ref), "/slam_pose": (t, est)})
    return tmp_path, t, est, ref


EVALUATE = ("metric", "evaluate", "--slam")


def _json(capsys, argv):
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_tum_carmen_and_bag_agree(recorded, capsys):
    d, t, est, ref = recorded
    common = ["--pairs", "3000", "--seed", "3", "--json"]
    tum = _json(capsys, [*EVALUATE, str(d / "slam.tum"), "--gt", str(d / "gt.tum"), *common])
    log = _json(capsys, [*EVALUATE, str(d / "slam.log.gz"), "--gt", str(d / "gt.log"), *common])
    bag = _json(capsys, [*EVALUATE, str(d / "run.bag"), "--slam-topic", "/slam_pose",
                         "--gt", str(d / "run.bag"), "--gt-topic", "/ground_truth", *common])
    expected = evaluate_against_reference(est, ref, n_pairs=3000, seed=3)
    for out in (tum, log, bag):
        assert out["info"]["associated"] == 400
        for key, stat in expected.stats.items():
            assert out["stats"][key]["mean"] == pytest.approx(stat.mean, rel=1e-9, abs=1e-12)
            assert out["stats"][key]["n"] == 3000


def test_table_output_and_json_file(recorded, capsys):
    d, *_ = recorded
    assert main(["metric", "evaluate", "--slam", str(d / "slam.tum"), "--gt", str(d / "gt.tum"),
                 "--pairs", "consecutive", "--out", str(d / "res.json")]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("Abs translational error") and lines[0].endswith(" m")
    assert lines[3].startswith("Sqr rotational error") and "N = 399 relations" in lines[4]
    assert json.loads((d / "res.json").read_text())["stats"]["trans_abs"]["n"] == 399


def test_relations_round_trip_through_file(recorded, capsys):
    d, t, est, ref = recorded
    assert main(["metric", "relations", "--gt", str(d / "gt.tum"), "--pairs", "700", "--seed", "1",
                 "--out", str(d / "gt.relations")]) == 0
    capsys.readouterr()
    via_file = _json(capsys, ["metric", "evaluate", "--slam", str(d / "slam.log.gz"),
                              "--relations", str(d / "gt.relations"), "--json"])
    direct = evaluate_against_reference(est, ref, n_pairs=700, seed=1)
    assert via_file["stats"]["trans_abs"]["n"] == 700
    assert via_file["stats"]["trans_abs"]["mean"] == pytest.approx(
        direct.stats["trans_abs"].mean, rel=1e-9)
    assert via_file["stats"]["rot_sqr"]["mean"] == pytest.approx(
        direct.stats["rot_sqr"].mean, rel=1e-9)


def test_auto_pairs_and_odometry_field(shared_data, capsys):
    log = str(shared_data / "slam_inputs" / "freiburg-101.log.gz")
    out = _json(capsys, [*EVALUATE, log, "--slam-field", "odom", "--gt", log, "--json"])
    assert out["info"]["associated"] == 292 and out["stats"]["trans_abs"]["mean"] > 5
    assert "sample_size" in out["info"]


def test_adjust_drops_truncated_line(tmp_path, capsys):
    path = tmp_path / "gt.log"
    path.write_text("FLASER 0 1 2 3 1 2 3 10.0 h 10.0\nFLASER 0 1 2 3 1 2 3 11.0 h 11.0\n"
                    "FLASER 0 1 2\n")
    assert main(["metric", "adjust", str(path)]) == 0
    assert "dropped" in capsys.readouterr().out
    assert path.read_text().count("\n") == 2


def _fails(capsys, argv, *words):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("slam-predict metric: error:")
    for w in words:
        assert w in err
    return err


def test_bad_inputs_exit_2_with_one_line(recorded, capsys):
    d, *_ = recorded
    slam, gt = str(d / "slam.tum"), str(d / "gt.tum")
    _fails(capsys, [*EVALUATE, str(d / "none.tum"), "--gt", gt], "none.tum", "not found")
    _fails(capsys, ["metric", "evaluate", "--slam", slam], "--gt FILE or --relations")
    _fails(capsys, ["metric", "evaluate", "--slam", slam, "--gt", gt, "--pairs", "many"], "--pairs")
    _fails(capsys, ["metric", "evaluate", "--slam", slam, "--gt", gt, "--pairs", "0"], "at least 1")
    (d / "traj.xyz").write_text("1 2 3\n")
    _fails(capsys, [*EVALUATE, str(d / "traj.xyz"), "--gt", gt], "traj.xyz", "--format")
    _fails(capsys, [*EVALUATE, str(d / "run.bag"), "--gt", gt], "run.bag", "topic")
    _fails(capsys, ["metric", "evaluate", "--slam", str(d / "run.bag"), "--slam-topic", "/slam",
                    "--gt", gt], "/slam not in bag", "did you mean '/slam_pose'")
    (d / "bad.tum").write_text("1 0 0 0 0 0 0 1\n2 0 0 0 0 0 zero 1\n")
    _fails(capsys, [*EVALUATE, str(d / "bad.tum"), "--gt", gt], "bad.tum:2", "non-numeric")
    (d / "bad.log").write_text("FLASER 0 1 2 x 1 2 3 10.0 h 10.0\n"
                               "FLASER 0 1 2 3 1 2 3 11.0 h 11.0\n")
    _fails(capsys, [*EVALUATE, str(d / "bad.log"), "--gt", gt], "bad.log:1", "FLASER")
    _fails(capsys, [*EVALUATE, slam, "--gt", gt, "--relations", gt], "not both")
    write_tum(d / "late.tum", 5000.0 + np.arange(3), np.zeros((3, 3)))
    _fails(capsys, [*EVALUATE, str(d / "late.tum"), "--gt", gt], "late.tum", "matched")
    (d / "x.bag").write_text("not a bag")
    _fails(capsys, [*EVALUATE, str(d / "x.bag"), "--slam-topic", "/a", "--gt", gt],
           "x.bag", "cannot open ROS bag")
    _fails(capsys, ["metric", "relations", "--gt", gt, "--pairs", "0", "--out", str(d / "r.rel")],
           "--pairs")
    assert not (d / "r.rel").exists()
    _fails(capsys, ["metric"], "choose an action")
