"""Robot-file mistakes a user makes, through the real CLI: each is refused with exit 2 and one
line on stderr that names the file and, where one applies, says what was probably meant; nothing
is written. ``--force`` accepts a file that is legal but implausible (a unit mistake)."""
from __future__ import annotations

import math
from pathlib import Path

import pytest
from robot_runs import ROOT, TINY

from slam_predict.cli.main import main
from slam_predict.robot_file import load_robot

GOOD = {"name": "r", "range_max": "5.6", "range_min": "0.02", "fov": "fov: 240.0",
        "samples": "683", "rate_hz": "10.0", "noise_std": "0.0",
        "odom_error": "odom_error: [0.01, 0.02, 2.0]", "footprint_side": "0.3",
        "max_vel_x": "0.5", "max_vel_theta": "1.0"}


def robot_text(**changes: str) -> str:
    v = {**GOOD, **changes}
    return (f"name: {v['name']}\nlaser:\n  range_max: {v['range_max']}\n"
            f"  range_min: {v['range_min']}\n  {v['fov']}\n  samples: {v['samples']}\n"
            f"  rate_hz: {v['rate_hz']}\n  noise_std: {v['noise_std']}\n{v['odom_error']}\n"
            f"footprint_side: {v['footprint_side']}\nmax_vel_x: {v['max_vel_x']}\n"
            f"max_vel_theta: {v['max_vel_theta']}\n")


# (case, file text or None for a folder, words the one line must hold: the problem and the hint)
MISTAKES = [
    ("fov in radians", robot_text(fov="fov: 6.28"), ["looks like radians", "fov_rad"]),
    ("fov both ways", robot_text(fov="fov: 240.0\n  fov_rad: 4.19"), ["not both"]),
    ("fov_rad not a number", robot_text(fov="fov_rad: wide"),
     ["'laser.fov_rad' must be a number"]),
    ("fov_rad in degrees", robot_text(fov="fov_rad: 240"), ["'laser.fov_rad' must be in",
                                                             "degrees? write laser.fov"]),
    ("fov_rad far too narrow", robot_text(fov="fov_rad: 0.05"),
     ["laser.fov_rad 0.05 rad is 2.86 deg", "narrower than any planar laser"]),
    ("a LaserScan's angles", robot_text(fov="angle_min: -2.09\n  angle_max: 2.09"),
     ["'angle_min'", "write laser.fov_rad = angle_max - angle_min"]),
    ("mounting yaw in radians", robot_text(fov="fov: 240.0\n  pose: [0.1, 0.0, 3.1416]"),
     ["laser.pose yaw 3.1416 looks like radians", "(180)"]),
    ("laser key at the top level", robot_text(odom_error="odom_error: [0.01, 0.02, 2.0]\n"
                                                         "pose: [0.1, 0.0, 0.0]"),
     ["'pose' at the top level", "belongs in the laser: section"]),
    ("range in mm", robot_text(range_max="12000"),
     ["beyond any planar laser", "12 m if it was mm"]),
    ("range too long", robot_text(range_max="150"), ["beyond any planar laser", "metres"]),
    ("range in km or cm", robot_text(range_max="0.1", range_min="0.0"),
     ["shorter than any planar laser"]),
    ("range_min in mm", robot_text(range_max="30", range_min="20"),
     ["laser.range_min 20 m is longer than any planar laser's minimum range"]),
    ("a LaserScan's range name", robot_text().replace("range_max", "max_range"),
     ["did you mean 'range_max'"]),
    ("one beam", robot_text(samples="1"), ["coarser than any planar laser", "241 for 1 deg"]),
    ("ten beams", robot_text(samples="10"), ["coarser than any planar laser"]),
    ("samples not a number", robot_text(samples="many"), ["'laser.samples' must be"]),
    ("yaw of 0.1 rad/rad", robot_text(odom_error="odom_error: [0.01, 0.02, 0.1]"),
     ["far below any real robot", "5.73 if 0.1 was rad/rad"]),
    ("yaw in rad/rad", robot_text(odom_error="odom_error: [0.01, 0.02, 0.0349]"),
     ["far below any real robot", "2 if 0.0349 was rad/rad", "odom_error_rad"]),
    ("yaw far too large", robot_text(odom_error="odom_error: [0.01, 0.02, 100]"),
     ["beyond any real robot", "degrees per radian"]),
    ("x/y in percent", robot_text(odom_error="odom_error: [1, 2, 2.0]"),
     ["not a percentage"]),
    ("odom error both ways",
     robot_text(odom_error="odom_error: [0.01, 0.02, 2.0]\nodom_error_rad: [0.01, 0.02, 0.03]"),
     ["not both"]),
    ("odom_error_rad in deg/rad", robot_text(odom_error="odom_error_rad: [0.01, 0.02, 2.0]"),
     ["odom_error_rad yaw 2 rad/rad is beyond any real robot's", "or write odom_error"]),
    ("odom_error_rad too short", robot_text(odom_error="odom_error_rad: [0.01, 0.03]"),
     ["'odom_error_rad' must be [x m/m, y m/m, yaw rad/rad]"]),
    ("odom error not a list", robot_text(odom_error="odom_error: 2.0"), ["'odom_error'"]),
    ("scan rate in rpm", robot_text(rate_hz="600"), ["scans per second"]),
    ("noise in mm", robot_text(noise_std="20"), ["noise_std is in metres"]),
    ("footprint in mm", robot_text(footprint_side="300"), ["footprint_side", "in metres"]),
    ("footprint in m but tiny", robot_text(footprint_side="0.01"), ["outside indoor robots"]),
    ("speed in km/h", robot_text(max_vel_x="30"), ["metres per second"]),
    ("turn rate in deg/s", robot_text(max_vel_theta="90"), ["radians per second"]),
    ("negative range", robot_text(range_max="-3"), ["'laser.range_max' must be > 0"]),
    ("unknown key", robot_text().replace("rate_hz", "rate"), ["did you mean 'rate_hz'"]),
    ("empty file", "", ["the robot file is empty"]),
    ("only a comment", "# my robot\n", ["the robot file is empty"]),
    ("a list", "- range_max: 5.6\n- fov: 240\n", ["top level must be a mapping"]),
    ("a folder", None, ["robot file is not a regular file"]),
    ("unknown shipped name", "urg_240", ["did you mean 'urg_240_5p6'"]),
]


def robot_argument(tmp_path: Path, case: str, text: str | None) -> str:
    if text is None:
        (tmp_path / "robot.yaml").mkdir()
        return str(tmp_path / "robot.yaml")
    if case == "unknown shipped name":
        return text
    (tmp_path / "robot.yaml").write_text(text)
    return str(tmp_path / "robot.yaml")


@pytest.mark.parametrize("case, text, words", MISTAKES, ids=[m[0] for m in MISTAKES])
@pytest.mark.parametrize("command", ["collect", "predict"])
def test_each_mistake_is_one_line_exit_2_and_nothing_written(tmp_path, capsys, case, text, words,
                                                             command):
    robot = robot_argument(tmp_path, case, text)
    out = tmp_path / "out"
    argv = {"collect": ["collect", str(TINY), "--runs", "1", "--out", str(out)],
            "predict": ["predict", str(TINY), "--simulate", "1", "--out", str(out)]}[command]
    assert main([*argv, "--robot", robot, "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and robot in err, err
    assert all(word in err for word in words), err
    assert not out.exists()


def test_at_least_twenty_mistakes_are_covered():
    assert len(MISTAKES) >= 20


def test_force_accepts_an_implausible_robot_and_logs_why(tmp_path, caplog):
    path = tmp_path / "robot.yaml"
    path.write_text(robot_text(range_max="12000"))
    robot = load_robot(path, force=True)
    assert robot.laser.range_max == 12000.0
    assert "beyond any planar laser" in caplog.text and "--force" in caplog.text


def test_predict_force_takes_the_implausible_robot(tmp_path, capsys, caplog):
    path = tmp_path / "robot.yaml"
    path.write_text(robot_text(fov="fov: 6.28"))
    code = main(["predict", str(TINY), "--robot", str(path), "--force", "--json"])
    err = capsys.readouterr().err
    assert code == 0, err
    assert "looks like radians" in caplog.text and "used as written" in caplog.text


def test_radian_spellings_are_the_same_robot(tmp_path):
    degrees = tmp_path / "deg.yaml"
    degrees.write_text(robot_text(fov="fov: 240.0", odom_error="odom_error: [0.01, 0.02, 2.0]"))
    radians = tmp_path / "rad.yaml"
    radians.write_text(robot_text(fov=f"fov_rad: {math.radians(240.0)!r}",
                                  odom_error=f"odom_error_rad: [0.01, 0.02, "
                                             f"{math.radians(2.0)!r}]"))
    ours, theirs = (load_robot(p).to_sensor_config() for p in (degrees, radians))
    assert theirs.laser.fov == pytest.approx(ours.laser.fov, rel=1e-15)
    assert theirs.odom.error == pytest.approx(ours.odom.error, rel=1e-15)


def test_a_shipped_robot_is_found_by_name():
    by_name = load_robot("urg_240_5p6")
    by_path = load_robot(ROOT / "config" / "robots" / "urg_240_5p6.yaml")
    assert by_name == by_path


@pytest.mark.parametrize("name", sorted(p.stem for p in (ROOT / "config" / "robots").glob("*")))
def test_shipped_robots_are_plausible(name):
    load_robot(name)        # raises on an implausible one


def test_a_robot_file_named_as_the_settings_simulator_config_says_use_robot(tmp_path, capsys):
    settings = tmp_path / "s.yaml"
    settings.write_text(f"extends: {ROOT / 'config' / 'collect.yaml'}\n"
                        f"robot: {ROOT / 'config' / 'robots' / 'urg_240_5p6.yaml'}\n")
    out = tmp_path / "out"
    assert main(["collect", str(TINY), "--settings", str(settings), "--runs", "1",
                 "--out", str(out), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "is a robot description file" in err and "--robot" in err
    assert not out.exists()
