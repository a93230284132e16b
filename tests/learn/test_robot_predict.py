"""The robot-aware model folder: card, round trip, refusals, domain warnings, partial
dependence and prediction speed."""
from __future__ import annotations

import json
import shutil
import time

import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.learn.model import resolve_store
from slam_predict.learn.robot.plain import PlainComponentModel
from slam_predict.learn.robot.predict import RobotModel
from slam_predict.learn.robot.train import build_card, fit_all, plain_forms, save_robot_store
from slam_predict.learn.store import CARD

from . import robot_synthetic as syn

PLAN = {"building_area": 800.0, "building_perimeter": 130.0,
        "voronoi_traversal_distance": 320.0, "voronoi_traversal_rotation": 40.0}
ROBOT = {"laser_range_max_m": 12.0, "laser_fov_deg": 270.0, "odom_xy_error": 0.01,
         "odom_yaw_error": 0.035}
BEST = {"trans_mean": "gradient_boosting", "trans_std": "elasticnet", "rot_mean": "elasticnet",
        "rot_std": "elasticnet"}


@pytest.fixture(scope="module")
def trained(tmp_path_factory):
    """(folder, in-memory fitted models, dataset) of a model trained on the synthetic campaign."""
    folder = tmp_path_factory.mktemp("robot_models")
    worlds, robots, _ = syn.campaign(folder / "data")
    data = syn.load(folder / "data", worlds)
    config = syn.fast_config(models=["elasticnet", "gradient_boosting"])
    tables = data.tables(config.plan_features)
    fitted = fit_all(tables, config)
    card = build_card(data, tables, config, [], BEST, fitted,
                      {"name": "own-robots", "feature_config": {"some": "config"}})
    from slam_predict.learn.dataset import to_csv_text

    save_robot_store(folder / "models" / "own-robots", card, fitted,
                     to_csv_text(data.point_dataset(config.plan_features)),
                     plain_forms(fitted, tables.point_X))
    return folder / "models" / "own-robots", fitted, data


def test_card_says_what_the_models_were_trained_on(trained):
    folder, _, data = trained
    card = json.loads((folder / CARD).read_text())
    assert card["kind"] == "robots" and card["name"] == "own-robots"
    assert card["features"] == list(PLAN) and card["robot_inputs"] == list(ROBOT)
    assert set(card["input_ranges"]) == set(PLAN) | set(ROBOT)
    low, high = card["input_ranges"]["laser_range_max_m"]
    assert 3.5 <= low < high <= 30.0
    assert card["design"]["buildings"] == data.worlds and len(card["design"]["configs"]) == 6
    assert card["design"]["angular_resolution_deg"] == [0.5] and card["interval_runs"] == 2
    assert {c: e["best"] for c, e in card["components"].items()} == BEST
    assert card["feature_version"] == "synthetic-v1"
    assert card["slam_config_hash"].split(",") == data.config_hashes()["gmapping"]
    assert card["max_urange_m"] == 30.0 and card["design"]["bounds"] is None
    assert card["odom_model"] == "uniform_per_run"
    components = ("trans_mean", "trans_std", "rot_mean", "rot_std")
    assert set(card["files"]) == {"training_points.csv", *(f"{c}.joblib" for c in components),
                                  *(f"{c}.plain.json" for c in components)}
    assert all(entry["plain"] for comp in card["components"].values()
               for entry in comp["models"].values())


def test_round_trip_gives_identical_predictions(trained):
    folder, fitted, data = trained
    model = RobotModel.load(folder)
    assert model.feature_config == {"some": "config"}
    assert all(isinstance(m, PlainComponentModel) for m in model.models.values())
    for members in data.groups[:10]:
        point = members[0]
        plan = {k: data.features[point.world][k] for k in PLAN}
        result = model.predict(plan, point.robot)
        x = model.row(plan, point.robot)
        for component, entry in result.items():
            direct = fitted[component][BEST[component]]
            value = direct.predict(x)[0]
            plain = model.models[component]
            assert plain.predict(x)[0] == pytest.approx(value, rel=1e-9)
            low, high = (direct.interval(x, 0.9, 2) if "std" in component
                         else direct.interval(x, 0.9))[0]
            plain_low, plain_high = (plain.interval(x, 0.9, 2) if "std" in component
                                     else plain.interval(x, 0.9))[0]
            assert (plain_low, plain_high) == pytest.approx((low, high), rel=1e-9)
            if model.monotone_by_construction(plain):      # else read from the envelope
                assert entry["value"] == pytest.approx(value, rel=1e-9)
                assert entry["low"] == pytest.approx(min(low, value), rel=1e-9)
                assert entry["high"] == pytest.approx(max(high, value), rel=1e-9)
            assert entry["model"] == f"own-robots/{BEST[component]}"
            assert entry["unit"] == ("m" if component.startswith("trans") else "rad")


def test_predict_is_fast_and_intervals_narrow_with_lower_confidence(trained):
    model = RobotModel.load(trained[0])
    start = time.perf_counter()
    wide = model.predict(PLAN, ROBOT)
    narrow = model.predict(PLAN, ROBOT, confidence=0.5)
    assert time.perf_counter() - start < 0.5
    for component, entry in wide.items():
        assert 0 < entry["low"] <= entry["value"] <= entry["high"]
        assert narrow[component]["high"] - narrow[component]["low"] < entry["high"] - entry["low"]
    truth = syn.expected(PLAN, {"range_max": 12.0, "fov": 270.0, "xy": 0.01, "yaw": 0.035})[0]
    assert wide["trans_mean"]["low"] <= truth <= wide["trans_mean"]["high"]
    with pytest.raises(InputError, match="confidence must lie in"):
        model.predict(PLAN, ROBOT, confidence=1.5)


def test_missing_inputs_are_one_line_errors(trained):
    model = RobotModel.load(trained[0])
    robot = {k: v for k, v in ROBOT.items() if k != "odom_yaw_error"}
    robot["odom_yaw_eror"] = 0.03
    with pytest.raises(InputError, match="robot input 'odom_yaw_error' needed by model "
                                         "own-robots is missing .did you mean"):
        model.predict(PLAN, robot)
    with pytest.raises(InputError, match="plan feature 'building_area'"):
        model.predict({}, ROBOT)


def test_domain_warnings(trained):
    model = RobotModel.load(trained[0])
    assert model.domain_warnings(PLAN, ROBOT, angular_resolution_deg=0.5) == []
    far = dict(ROBOT, laser_range_max_m=80.0)
    lines = model.domain_warnings(dict(PLAN, building_area=1e5), far, 0.25)
    low, high = model.card["input_ranges"]["laser_range_max_m"]
    assert any(line.startswith(f"laser_range_max_m = 80 m is outside the training range "
                               f"[{low:.4g}, {high:.4g}] m") for line in lines)
    assert any(line.startswith("building_area = 1e+05 is outside") for line in lines)
    assert any("angular resolution 0.25 deg is finer than every training run's (0.5 deg"
               in line for line in lines)
    assert len(lines) == 3
    assert all("--simulate 3" in line for line in lines)     # each says what to do
    # a bound met up to a unit conversion's rounding (270° from 4.712389 rad) is inside
    high = model.card["input_ranges"]["laser_fov_deg"][1]
    assert model.domain_warnings(PLAN, dict(ROBOT, laser_fov_deg=high * (1 + 4e-9))) == []
    assert model.domain_warnings(PLAN, dict(ROBOT, laser_fov_deg=high * 1.001)) != []
    # design configurations on the diagonal of (xy, yaw): the opposite corner lies far away
    model.card["design"]["configs"] = {f"c{i}": {"odom_xy_error": 0.004 * i,
                                                 "odom_yaw_error": 0.014 * i} for i in range(6)}
    corner = dict(ROBOT, odom_xy_error=0.02, odom_yaw_error=0.0)
    note = model.odom_gap_warning(corner)
    assert note is not None and "lie far from every design configuration" in note
    assert model.odom_gap_warning(dict(ROBOT, odom_xy_error=0.008, odom_yaw_error=0.028)) is None


def test_a_robot_with_another_odometry_model_is_warned_about(trained):
    """Bounds drawn per run and Stage's fixed biases share numbers, not meaning."""
    model = RobotModel.load(trained[0])
    assert model.odom_model_warning("uniform_per_run") is None
    assert model.odom_model_warning("none") is None
    note = model.odom_model_warning("fixed")
    assert note is not None and "odometry model is fixed" in note and "uniform_per_run" in note
    model.card["odom_model"] = "fixed"
    assert model.odom_model_warning("fixed") is None
    assert "training runs used fixed" in model.odom_model_warning("uniform_per_run")
    del model.card["odom_model"]                      # cards before the field: bounds
    assert model.odom_model_warning("fixed") is not None


def test_partial_dependence_is_monotone_in_range(trained):
    """The truth falls with the laser range (range^-0.3): so does the PDP of the
    gradient-boosting mean model, and it rises with the odometry errors."""
    model = RobotModel.load(trained[0])
    grid, values = model.partial_dependence("trans_mean", "laser_range_max_m", 12)
    assert len(grid) == 12 and np.all(np.diff(grid) > 0)
    assert np.all(np.diff(values) <= 0.01 * np.ptp(values))
    assert values[0] > 1.1 * values[-1]
    _, rising = model.partial_dependence("trans_mean", "odom_xy_error", 6)
    assert rising[-1] > rising[0]
    with pytest.raises(InputError, match="unknown robot input 'range'"):
        model.partial_dependence("trans_mean", "range")


def test_bad_folders_are_refused(trained, tmp_path):
    folder = tmp_path / "m"
    shutil.copytree(trained[0], folder)
    data = (folder / "rot_std.joblib").read_bytes()
    (folder / "rot_std.joblib").write_bytes(data[:-10])
    with pytest.raises(InputError, match="checksum differs") as err:
        RobotModel.load(folder)
    assert "rot_std.joblib" in err.value.one_line()
    with pytest.raises(InputError, match="model folder not found"):
        RobotModel.load(tmp_path / "nope")
    plan_only = tmp_path / "plan"
    shutil.copytree(trained[0], plan_only)
    card = json.loads((plan_only / CARD).read_text())
    del card["kind"]
    (plan_only / CARD).write_text(json.dumps(card))
    with pytest.raises(InputError, match=r"is a plan-only model \(kind plan\)"):
        RobotModel.load(plan_only)
    old = tmp_path / "old"
    shutil.copytree(trained[0], old)
    card = json.loads((old / CARD).read_text())
    del card["max_urange_m"]       # a card written before the range cap
    (old / CARD).write_text(json.dumps(card))
    with pytest.raises(InputError, match="missing 'max_urange_m'.*learn robots"):
        RobotModel.load(old)
    # the plan-only predict refuses a robot-aware folder by name and never picks it as best
    with pytest.raises(InputError, match="is a robot-aware model"):
        resolve_store(trained[0].parent, "own-robots", None, None)
    with pytest.raises(InputError, match="no model of gmapping.s error"):
        resolve_store(trained[0].parent, "best", None, None)


def test_resolution_warning_only_outside_the_trained_range(trained):
    """The card's trained resolutions are the range: inside it (1 % tolerance) no line;
    finer or coarser, a line that says which and what to do."""
    model = RobotModel.load(trained[0])
    model.card["design"]["angular_resolution_deg"] = [0.25, 0.5]
    assert model.resolution_range_deg() == (0.25, 0.5)
    for inside in (0.25, 0.36, 0.5, 0.504):
        assert model.resolution_warning(inside) is None
    finer, coarser = model.resolution_warning(0.1), model.resolution_warning(1.0)
    assert "finer than every training run's (0.25-0.5 deg" in finer
    assert "coarser" in coarser and "--simulate 3" in coarser
