"""The plan × robot input ``laser_blind_fraction``: tables, card, prediction and partial
dependence agree with the plan's sight-line curve read at the laser's range."""
from __future__ import annotations

import json

import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.features.sightline import (
    SightlineConfig,
    blind_fraction,
    curve_columns,
    sightline_features,
)
from slam_predict.learn.robot.inputs import ROBOT_INPUTS
from slam_predict.learn.robot.predict import RobotModel
from slam_predict.learn.store import CARD

from . import robot_synthetic as syn

ROBOT = {"laser_range_max_m": 6.0, "laser_fov_deg": 270.0, "odom_xy_error": 0.01,
         "odom_yaw_error": 0.035, "laser_resolution_deg": 0.5}


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sightline")
    worlds, robots, _ = syn.campaign(folder / "data", n_worlds=6, n_configs=4)
    return syn.load(folder / "data", worlds), worlds


def test_tables_read_each_building_s_curve_at_the_run_s_range(campaign):
    data, worlds = campaign
    tables = data.tables(syn.FAST_FEATURES, derived=True)
    assert tables.names == [*syn.FAST_FEATURES, "laser_blind_fraction", *ROBOT_INPUTS]
    j, k = tables.names.index("laser_blind_fraction"), tables.names.index("laser_range_max_m")
    for i, world in enumerate(tables.point_world):
        expected = blind_fraction(worlds[world], tables.point_X[i, k])
        assert tables.point_X[i, j] == pytest.approx(expected, rel=1e-12)
    assert data.tables(syn.FAST_FEATURES).names == [*syn.FAST_FEATURES, *ROBOT_INPUTS]


def test_a_feature_table_without_curves_is_refused_by_name(campaign):
    data, _ = campaign
    first = data.worlds[0]
    data.features[first] = {k: v for k, v in data.features[first].items()
                            if k not in curve_columns()}
    try:
        with pytest.raises(InputError, match=f"building '{first}' have no sight-line curve"):
            data.tables(syn.FAST_FEATURES, derived=True)
        assert "sightline_blind_1m" not in data.feature_names()
    finally:
        data.features[first].update(syn.sightline_curve(data.features[first]["building_area"]))


def test_model_predicts_and_plots_with_the_blind_fraction(robot_models_dir):
    folder = robot_models_dir / "own-robots"
    card = json.loads((folder / CARD).read_text())
    assert card["derived_inputs"] == ["laser_blind_fraction"]
    assert sorted(card["sightline_curves"]) == card["training_buildings"]
    assert card["sightline"]["ranges_m"][0] == 1.0 and "laser_blind_fraction" in \
        card["input_ranges"]
    model = RobotModel.load(folder)
    plan = {"building_area": 800.0, "building_perimeter": 130.0,
            "voronoi_traversal_distance": 320.0, "voronoi_traversal_rotation": 40.0,
            **syn.sightline_curve(800.0)}
    row = model.row(plan, ROBOT)[0]
    assert row[model.names.index("laser_blind_fraction")] == pytest.approx(
        blind_fraction(plan, 6.0), rel=1e-12)
    assert all(model.predict(plan, ROBOT)[c]["value"] > 0 for c in model.models)
    with pytest.raises(InputError, match="sight-line curve"):
        model.predict({k: v for k, v in plan.items() if k not in curve_columns()}, ROBOT)
    # partial dependence over the range moves the blind fraction of every training point
    grid, values = model.partial_dependence("trans_mean", "laser_range_max_m", 4)
    j, k = model.names.index("laser_blind_fraction"), model.names.index("laser_range_max_m")
    for g, value in zip(grid, values, strict=True):
        X = model.points.copy()
        X[:, k] = g
        X[:, j] = [blind_fraction(card["sightline_curves"][w], g) for w in model.point_worlds]
        assert value == pytest.approx(float(np.mean(model.models["trans_mean"].predict(X))),
                                      rel=1e-12)


@pytest.mark.parametrize("feature", ["sightline_isotropy", "floor_elongation"])
def test_a_sampling_feature_alone_makes_the_card_keep_the_sampling(campaign, feature):
    from slam_predict.learn.robot.train import _sightline_entries

    data, _ = campaign
    assert _sightline_entries(data, [], ["building_area"]) == {}
    alone = _sightline_entries(data, [], ["building_area", feature])
    assert set(alone) == {"sightline"} and alone["sightline"]["isotropy_range_m"] == 30.0
    both = _sightline_entries(data, ["laser_blind_fraction"], ["building_area"])
    assert set(both) == {"sightline", "sightline_curves"}


def test_a_model_reading_the_isotropy_computes_the_sight_lines(robot_models_dir):
    from features.plans import Plan

    world = Plan(12.0, 12.0, 0.05).room("hall", (1.0, 1.0, 11.0, 11.0)).world()   # square
    model = RobotModel.load(robot_models_dir / "own-robots")
    model.derived = []
    assert model.sightline_config is None
    model.names = [*model.names, "sightline_isotropy"]
    features = sightline_features(world, SightlineConfig(**model.sightline_config))
    assert 0.8 < features["sightline_isotropy"] <= 1.0 and set(curve_columns()) <= set(features)
    model.names = [n for n in model.names if n != "sightline_isotropy"]
    assert model.sightline_config is None
    model.names = [*model.names, "floor_elongation"]
    features = sightline_features(world, SightlineConfig(**model.sightline_config))
    assert features["floor_elongation"] == pytest.approx(1.0)
