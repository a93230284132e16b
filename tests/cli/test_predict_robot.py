"""``slam-predict predict PLAN --robot FILE`` (and ``rosrun slam_predict predict``) with a
robot-aware model trained on the synthetic campaign (the session's ``robot_models_dir``): the
prediction, the robot inputs it took, domain warnings, and one-line errors (exit 2)."""
from __future__ import annotations

import contextlib
import io
import json
import math
import subprocess
import sys

import pytest

from slam_predict.cli.main import main
from slam_predict.features.plan import plan_features
from slam_predict.features.sightline import blind_fraction
from slam_predict.learn.robot.predict import RobotModel
from slam_predict.robot_file import load_robot
from slam_predict.world.load import load_plan

WORLD = "worlds/office_500.world"
ROBOTS = "config/robots"
COMPONENTS = ("trans_mean", "trans_std", "rot_mean", "rot_std")


def call(*argv) -> tuple[int, str, str]:
    """(exit code, stdout, stderr) of ``slam-predict predict ...``."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["predict", *argv])
    return code, out.getvalue(), err.getvalue()


@pytest.fixture(scope="module")
def lds(root, robot_models_dir):
    """The JSON result for the 360° 3.5 m LDS robot on office_500."""
    code, out, err = call(str(root / WORLD), "--robot", f"{root / ROBOTS}/lds_360_3p5.yaml",
                          "--models-dir", str(robot_models_dir), "--json")
    assert code == 0, err
    return json.loads(out)


def test_json_has_the_four_components_of_the_robot_aware_model(lds, root, robot_models_dir):
    assert lds["model_store"] == "own-robots" and lds["model_takes_robot"] is True
    assert lds["setting"] == "robots" and lds["confidence"] == 0.9
    assert list(lds)[:9] == ["world", "plan", "slam", "setting", "model_store",
                             "model_takes_robot", "robot", "failure", "confidence"]
    assert lds["slam"] == "gmapping"
    model = RobotModel.load(robot_models_dir / "own-robots")
    robot = load_robot(root / ROBOTS / "lds_360_3p5.yaml")
    plan = load_plan(root / WORLD)
    features = plan_features(plan, model.feature_config, model.sightline_config)
    expected = model.predict(features, model.inputs(robot))
    for comp in COMPONENTS:
        entry = lds[comp]
        assert entry["status"] == "ok" and entry["unit"] == ("m" if "trans" in comp else "rad")
        assert entry["model"] == expected[comp]["model"]
        assert entry["model"].startswith("own-robots/")
        for key in ("value", "low", "high"):
            assert entry[key] == pytest.approx(expected[comp][key], rel=1e-12)
        assert 0 <= entry["low"] <= entry["value"] <= entry["high"]
    assert lds["features"] == pytest.approx(features)
    assert lds["robot"] == {
        "file": f"{root / ROBOTS}/lds_360_3p5.yaml", "name": "lds_360_3p5",
        "inputs": model.inputs(robot), "laser_range_max_m": 3.5, "max_urange_m": 30.0,
        "angular_resolution_deg": pytest.approx(360.0 / 359.0),
        "derived": {"laser_blind_fraction": pytest.approx(
            blind_fraction(features, 3.5), rel=1e-12)}}
    assert 0.001 <= lds["robot"]["derived"]["laser_blind_fraction"] < 1.0


def test_domain_warnings_name_the_resolution(lds):
    """The LDS laser has 1° beams; the design's have 0.5°: the model learns the resolution,
    so its input range says it (one line, not a second one of its own)."""
    assert any(w.startswith("laser_resolution_deg = 1 deg is outside the training range "
                            "[0.5, 0.5] deg") and "--simulate 3" in w for w in lds["warnings"])
    assert not any("angular resolution" in w for w in lds["warnings"])
    assert not any(w.startswith("laser_range_max_m") for w in lds["warnings"])


def test_seed_robot_is_inside_the_design_range(root, robot_models_dir):
    """The seed study's 80 m laser is a 30 m robot input (GMapping's maxUrange): inside the
    design's 3.5-30 m, so no range warning; text output says what the model took."""
    code, out, err = call(str(root / WORLD), "--robot", f"{root / ROBOTS}/seed_realistic.yaml",
                          "--models-dir", str(robot_models_dir))
    assert code == 0, err
    lines = out.splitlines()
    assert lines[0] == (f"office_500: predicted GMapping localization error for robot "
                        f"seed_realistic ({root / ROBOTS}/seed_realistic.yaml)")
    assert lines[1].startswith("model own-robots (robot-aware: takes the robot into account), "
                               "90 % intervals; robot inputs: laser range 30 m used (laser "
                               "80 m, GMapping's maxUrange 30 m), fov 270°, beams every 0.5°, "
                               "odometry 0.01 m/m")
    for comp in COMPONENTS:
        assert any(line.startswith(f"  {comp} ") and "[own-robots/" in line for line in lines)
    warnings = [line for line in lines if line.startswith("warning: ")]
    robot_inputs = ("laser_range_max_m", "laser_fov_deg", "odom_xy_error", "odom_yaw_error")
    assert not any(name in w for w in warnings for name in robot_inputs), warnings
    assert not any("angular resolution" in w for w in warnings)


def test_one_component(root, robot_models_dir):
    code, out, err = call(str(root / WORLD), "--robot", f"{root / ROBOTS}/urg_240_5p6.yaml",
                          "--models-dir", str(robot_models_dir), "--component", "rot_mean",
                          "--json")
    assert code == 0, err
    result = json.loads(out)
    assert "rot_mean" in result and not set(COMPONENTS) - {"rot_mean"} & set(result)
    assert result["robot"]["inputs"]["laser_range_max_m"] == 5.6


def one_line_error(*argv) -> str:
    code, out, err = call(*argv)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and "Traceback" not in err and not out, err
    return lines[0]


def test_missing_robot_aware_model_says_how_to_train_one(root, tmp_path):
    (tmp_path / "models").mkdir()
    err = one_line_error(str(root / WORLD), "--robot", f"{root / ROBOTS}/lds_360_3p5.yaml",
                         "--models-dir", str(tmp_path / "models"))
    assert f"no robot-aware model folder {tmp_path / 'models' / 'own-robots'}" in err
    assert "slam-predict learn train --runs" in err and "--name own-robots" in err


def test_other_refusals(root, robot_models_dir, tmp_path):
    lds = f"{root / ROBOTS}/lds_360_3p5.yaml"
    err = one_line_error(str(root / WORLD), "--robot", lds, "--model", "thesis-realistic")
    assert "model thesis-realistic is a plan-only model" in err and "--robot needs" in err
    err = one_line_error(str(root / WORLD), "--robot", lds, "--models-dir",
                         str(robot_models_dir), "--thesis-setting", "optimistic")
    assert "--thesis-setting applies to the plan-only models" in err
    bad = tmp_path / "bad.yaml"
    bad.write_text((root / ROBOTS / "lds_360_3p5.yaml").read_text().replace("fov: 360.0",
                                                                            "fov: 400.0"))
    err = one_line_error(str(root / WORLD), "--robot", str(bad), "--models-dir",
                         str(tmp_path))          # the bad robot file before the missing model
    assert "bad.yaml" in err and "fov" in err


def test_without_robot_the_plan_only_model_predicts(root, robot_models_dir, monkeypatch):
    """The robot-aware folder beside the plan-only ones changes nothing without --robot."""
    monkeypatch.chdir(root)
    code, out, err = call(WORLD, "--json", "--component", "trans_mean")
    assert code == 0, err
    result = json.loads(out)
    assert result["model_store"] == "thesis-realistic" and "robot" not in result
    assert "model_takes_robot" not in result


def test_rosrun_script_passes_robot_through(root, robot_models_dir):
    proc = subprocess.run([sys.executable, str(root / "scripts" / "predict"), WORLD, "--robot",
                           f"{ROBOTS}/urg_240_5p6.yaml", "--models-dir", str(robot_models_dir),
                           "--json", "__name:=predict"], cwd=root, capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    result = json.loads(proc.stdout)
    assert result["model_takes_robot"] is True and result["robot"]["name"] == "urg_240_5p6"
    assert all(math.isfinite(result[c]["value"]) for c in COMPONENTS)
    proc = subprocess.run([sys.executable, str(root / "scripts" / "predict"), WORLD, "--robot",
                           f"{ROBOTS}/urg_240_5p6.yaml", "--models-dir", str(root / "nope")],
                          cwd=root, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 2 and "no robot-aware model folder" in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1


def test_failure_probability_in_json_and_text(lds, root, robot_models_dir):
    """Beside the four components: the probability that an exploration maps less than the
    card's coverage threshold, with its one-line meaning; the old footnote is gone."""
    failure = lds["failure"]
    assert 0.0 <= failure["probability"] <= 1.0 and failure["coverage_threshold"] == 0.9
    assert failure["training_runs"] > 0
    assert not any("mapped less than" in w for w in lds["warnings"])
    code, out, err = call(str(root / WORLD), "--robot", f"{root / ROBOTS}/lds_360_3p5.yaml",
                          "--models-dir", str(robot_models_dir))
    assert code == 0, err
    lines = out.splitlines()
    line = next(x for x in lines if x.startswith("  failure    P(exploration maps < 90 % of "
                                                 "the floor)"))
    assert line.endswith(f"{100 * failure['probability']:.0f} %")
    assert any("the errors above describe explorations that succeed" in x for x in lines)
