"""``slam-predict sim drive``: scripted runs, CARMEN/TUM outputs, bad input."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from slam_predict.cli.main import main
from slam_predict.formats.carmen import read_log
from slam_predict.formats.tum import read_tum
from slam_predict.geometry import compose, ominus
from slam_predict.sim import OdomConfig, SimConfig, Simulator
from slam_predict.sim.drive import FollowerConfig, drive
from slam_predict.world.load import load_plan

WAYPOINTS = [[0.0, 0.0], [0.0, 2.0], [3.0, 2.0], [3.0, -2.0]]


@pytest.fixture(scope="module")
def room(root) -> Path:
    return root / "tests" / "data" / "stage_sim_room.world"


def write_waypoints(folder: Path, points, name="path.yaml") -> Path:
    path = folder / name
    path.write_text("waypoints:\n" + "".join(f"  - [{x}, {y}]\n" for x, y in points))
    return path


def test_follower_reaches_every_waypoint(room):
    world = load_plan(room)
    sim = Simulator(world, SimConfig(odom=OdomConfig(model="none")), np.random.default_rng(0))
    log = drive(sim, np.array(WAYPOINTS), FollowerConfig())
    poses = np.array(log.true_poses)
    for point in WAYPOINTS:
        assert np.hypot(*(poses[:, :2] - point).T).min() <= 0.1 + 1e-9
    assert log.stalled_steps == 0
    assert log.velocities[-1] == (0.0, 0.0)
    assert 11.0 < log.path_length() < 13.0  # 2 + 2 + 3 + 4 m of straight legs (+ ramps)


def test_drive_writes_carmen_and_tum(room, tmp_path):
    path = write_waypoints(tmp_path, WAYPOINTS)
    out = tmp_path / "run"
    assert main(["sim", "drive", str(room), "--path", str(path), "--out", str(out),
                 "--seed", "5"]) == 0
    meta = json.loads((out / "run.json").read_text())
    assert meta["seed"] == 5 and meta["odom_error"]["model"] == "uniform_per_run"
    log = read_log(out / "run.log")
    t_true, true_poses = read_tum(out / "ground_truth.tum")
    t_odom, odom_poses = read_tum(out / "odometry.tum")
    assert len(log.scans) == meta["scans"] == len(t_true) == meta["steps"]  # 10 Hz = step rate
    np.testing.assert_allclose(log.odometry.t, t_odom)
    np.testing.assert_allclose(log.odometry.poses, odom_poses, atol=1e-9)
    scan = log.scans[len(log.scans) // 2]
    assert scan.kind == "ROBOTLASER1" and len(scan.ranges) == 541
    assert scan.fov == pytest.approx(math.radians(270))
    k = int(np.argmin(np.abs(t_true - scan.timestamp)))
    np.testing.assert_allclose(scan.pose, true_poses[k], atol=1e-9)  # laser at the centre
    np.testing.assert_allclose(scan.odom_pose, odom_poses[k], atol=1e-9)
    # the ranges are what the laser sees from the logged true pose
    world = load_plan(room)
    sim = Simulator(world, SimConfig(), np.random.default_rng(0))
    np.testing.assert_allclose(scan.ranges, sim.scan_from(true_poses[k]), atol=6e-4)
    # odometry error: bias drawn within the world file's bounds, odometry ≠ truth
    bias, bound = meta["odom_error"]["bias"], meta["odom_error"]["bound"]
    assert all(abs(b) <= e for b, e in zip(bias, bound, strict=False))
    drift = ominus(true_poses[-1], world.start_pose) - odom_poses[-1]
    assert 0 < np.hypot(*drift[:2]) < 0.01 * meta["distance_m"] * 3


def test_same_seed_same_files(room, tmp_path):
    path = write_waypoints(tmp_path, WAYPOINTS[:2])
    texts = []
    for name in ("a", "b"):
        assert main(["sim", "drive", str(room), "--path", str(path), "--out",
                     str(tmp_path / name), "--seed", "9", "--odom-model",
                     "gaussian_per_step"]) == 0
        texts.append((tmp_path / name / "run.log").read_text())
    assert texts[0] == texts[1]


def test_drive_with_stage_ranger(room, tmp_path):
    path = write_waypoints(tmp_path, WAYPOINTS[:2])
    out = tmp_path / "stage"
    assert main(["sim", "drive", str(room), "--path", str(path), "--out", str(out),
                 "--ranger-model", "stage"]) == 0
    meta = json.loads((out / "run.json").read_text())
    assert meta["sim_config"]["ranger_model"] == "stage"
    scan = read_log(out / "run.log").scans[5]
    world = load_plan(room)
    config = SimConfig(ranger_model="stage")
    sim = Simulator(world, config, np.random.default_rng(0))
    exact = Simulator(world, SimConfig(), np.random.default_rng(0))
    pose = np.asarray(scan.pose)
    np.testing.assert_allclose(scan.ranges, sim.scan_from(pose), atol=6e-4)
    assert np.abs(np.asarray(scan.ranges) - exact.scan_from(pose)).max() > 6e-3


def test_none_model_odometry_equals_truth(room, tmp_path):
    path = write_waypoints(tmp_path, WAYPOINTS[:3])
    out = tmp_path / "none"
    assert main(["sim", "drive", str(room), "--path", str(path), "--out", str(out),
                 "--odom-model", "none"]) == 0
    _, truth = read_tum(out / "ground_truth.tum")
    _, odom = read_tum(out / "odometry.tum")
    start = load_plan(room).start_pose
    np.testing.assert_allclose(compose(start, odom), truth, atol=1e-9)


@pytest.mark.parametrize("case,message", [
    ("missing", "waypoint file not found"),
    ("in_wall", "waypoint 2 (1.20, 1.00) is inside a wall"),
    ("outside", "waypoint 1 (40.00, 0.00) is outside the map"),
    ("malformed", "waypoint 1 must be [x, y] in metres"),
    ("empty", "expected a non-empty list"),
    ("yaml", "YAML syntax error"),
    ("blocked", "path blocked: the robot is stuck"),
])
def test_bad_waypoints_exit_2_with_one_line(room, tmp_path, capsys, case, message):
    path = tmp_path / "path.yaml"
    content = {
        "in_wall": "waypoints:\n  - [0, 0]\n  - [1.2, 1.0]\n",
        "outside": "waypoints: [[40, 0]]\n",
        "malformed": "waypoints: [[1, 2, 3]]\n",
        "empty": "waypoints: []\n",
        "yaml": "waypoints: [[1, 2]\n",
        "blocked": "waypoints: [[-2.0, -2.0]]\n",
    }
    if case != "missing":
        path.write_text(content[case])
    out = tmp_path / "out"
    assert main(["sim", "drive", str(room), "--path", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert message in err and str(path) in err
    assert not out.exists()


def test_flaser_needs_a_180_degree_laser(room, tmp_path, capsys):
    path = write_waypoints(tmp_path, WAYPOINTS[:1])
    out = tmp_path / "out"
    assert main(["sim", "drive", str(room), "--path", str(path), "--out", str(out),
                 "--laser-message", "FLASER"]) == 2
    err = capsys.readouterr().err
    assert "FLASER lines assume a 180-degree laser" in err and str(room) in err
    assert not out.exists()


def test_bad_config_and_missing_world(room, tmp_path, capsys):
    path = write_waypoints(tmp_path, WAYPOINTS[:1])
    config = tmp_path / "robot.yaml"
    config.write_text("sim:\n  odom:\n    modle: none\n")
    assert main(["sim", "drive", str(room), "--path", str(path), "--out", str(tmp_path / "o"),
                 "--config", str(config)]) == 2
    err = capsys.readouterr().err
    assert "did you mean 'model'" in err and str(config) in err
    assert main(["sim", "drive", str(tmp_path / "nope.world"), "--path", str(path), "--out",
                 str(tmp_path / "o")]) == 2
    assert "nope.world" in capsys.readouterr().err


def test_sim_without_action_is_an_error(capsys):
    assert main(["sim"]) == 2
    assert "choose an action" in capsys.readouterr().err
