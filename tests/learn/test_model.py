"""load_model: one loader for both model families; the features come from features/."""
from __future__ import annotations

from pathlib import Path

import pytest

from slam_predict.errors import InputError
from slam_predict.features.plan import compute, plan_features
from slam_predict.features.sightline import SightlineConfig, sightline_features
from slam_predict.learn.card import PLAN_KIND, ROBOT_KIND, card_slam
from slam_predict.learn.model import PlanModel, check_slam, load_model
from slam_predict.learn.predict import predict_features
from slam_predict.learn.robot.predict import RobotModel
from slam_predict.learn.store import ModelStore
from slam_predict.world.load import load_plan

ROOT = Path(__file__).resolve().parents[2]
MODELS = ROOT / "models"


def test_load_model_returns_the_family_of_the_card():
    assert isinstance(load_model(MODELS / "thesis-realistic"), PlanModel)
    robots = load_model(MODELS / "own-robots")
    assert isinstance(robots, RobotModel) and robots.takes_robot
    assert load_model(MODELS / "own-robots", ROBOT_KIND).name == "own-robots"
    with pytest.raises(InputError, match="is a robot-aware model"):
        load_model(MODELS / "own-robots", PLAN_KIND)
    with pytest.raises(InputError, match="is a plan-only model"):
        load_model(MODELS / "thesis-realistic", ROBOT_KIND)
    with pytest.raises(InputError, match="model folder not found"):
        load_model(MODELS / "nope")


def test_slam_algorithm_is_the_cards_or_absent():
    card = load_model(MODELS / "thesis-realistic").card
    check_slam(None, card)
    check_slam("gmapping", card)
    check_slam("karto")                                   # a known algorithm, no card
    with pytest.raises(InputError, match="was trained on gmapping runs, not karto"):
        check_slam("karto", card)
    with pytest.raises(InputError, match="did you mean 'karto'"):
        check_slam("kartto")
    assert card_slam({"name": "old"}) == "gmapping" and card_slam({"slam": "karto"}) == "karto"


def test_plan_model_predicts_as_the_store_from_features_of_features_plan():
    world = load_plan(ROOT / "worlds" / "tiny.world")
    model = load_model(MODELS / "thesis-realistic")
    model.check_feature_version()
    assert model.sightline_config is None and not model.takes_robot
    features = plan_features(world, model.feature_config)
    assert features == compute(world, model.feature_config)
    expected = predict_features(features, ModelStore(MODELS / "thesis-realistic"))
    assert model.predict(features, slam="gmapping") == expected
    assert model.predict(features, component="rot_mean")["rot_mean"] == expected["rot_mean"]
    with pytest.raises(InputError, match="SLAM algorithm"):
        model.predict(features, slam="cartographer")


def test_robot_model_features_add_the_sight_lines_it_reads():
    world = load_plan(ROOT / "worlds" / "tiny.world")
    model = load_model(MODELS / "own-robots")
    assert model.sightline_config is not None and "ranges_m" not in model.sightline_config
    features = plan_features(world, model.feature_config, model.sightline_config)
    expected = dict(compute(world, model.feature_config),
                    **sightline_features(world, SightlineConfig(**model.sightline_config)))
    assert features == expected
    assert set(model.names) - set(model.derived) - set(features) == {
        "laser_range_max_m", "laser_fov_deg", "odom_xy_error", "odom_yaw_error",
        "laser_resolution_deg"}


def test_pickles_of_older_robot_folders_load_under_the_new_module_names():
    import sys

    from slam_predict.learn.robot.plain import LogScaleModel

    store = ModelStore(MODELS / "own-robots")
    for component in ("trans_mean", "rot_std"):
        assert isinstance(store.estimator(component), LogScaleModel)
    assert not [name for name in sys.modules if name.startswith("slam_predict.learn.robot_")]
