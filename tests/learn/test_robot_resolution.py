"""The laser's angular resolution as a fifth robot input (robot_learning.resolution_input):
learnt from runs at several resolutions, on the card, in prediction, without a direction."""
from __future__ import annotations

import json

import numpy as np
import pytest

from slam_predict.learn.robot.monotone_check import passes
from slam_predict.learn.robot.predict import RobotModel
from slam_predict.learn.robot.train import train_robot_store
from slam_predict.learn.store import CARD

from . import robot_synthetic as syn

RESOLUTIONS = (0.25, 0.5, 1.0)
BEST = {"trans_mean": "trend_boosting", "trans_std": "elasticnet",
        "rot_mean": "trend_boosting", "rot_std": "elasticnet"}


@pytest.fixture(scope="module")
def trained(tmp_path_factory):
    """(model folder, worlds) trained with the resolution input on a synthetic campaign whose
    robots each have one of three resolutions (finer errs more, syn.expected)."""
    folder = tmp_path_factory.mktemp("resolution")
    rng = np.random.default_rng(3)
    worlds = syn.buildings(12, rng)
    robots = [dict(r, resolution=RESOLUTIONS[i % 3])
              for i, r in enumerate(syn.robot_configs(9, rng))]
    syn.write_campaign(folder / "data", worlds, robots, 2, rng)
    data = syn.load(folder / "data", worlds)
    config = syn.fast_config(models=["elasticnet", "trend_boosting"], resolution_input=True)
    out = train_robot_store(data, config, [], BEST, folder / "model",
                            {"name": "res", "feature_config": {}})
    return out, worlds


def test_the_card_lists_the_resolution_with_its_trained_range(trained):
    folder, _ = trained
    card = json.loads((folder / CARD).read_text())
    assert card["robot_inputs"][-1] == "laser_resolution_deg"
    assert card["robot_units"]["laser_resolution_deg"] == "deg"
    assert card["input_ranges"]["laser_resolution_deg"] == [0.25, 1.0]
    assert card["design"]["angular_resolution_deg"] == list(RESOLUTIONS)
    header = (folder / "training_points.csv").read_text().splitlines()[0].split(",")
    assert "laser_resolution_deg" in header
    for component in ("trans_mean", "rot_mean"):   # checked at every trained resolution
        entry = card["components"][component]["models"]["trend_boosting"]
        assert passes(entry["monotone"]["worst_drop"])


def test_prediction_reads_the_resolution_and_follows_the_data(trained):
    """The same robot at 0.25° errs more than at 1° (the synthetic law: (res/0.5)^-0.3, ×1.5;
    the boosted trees, shrunk, give 1.19 with this seed), and
    inside the trained resolutions no resolution warning fires."""
    folder, worlds = trained
    model = RobotModel.load(folder)
    plan = dict(next(iter(worlds.values())))
    robot = {"laser_range_max_m": 12.0, "laser_fov_deg": 270.0, "odom_xy_error": 0.01,
             "odom_yaw_error": 0.035}
    fine = model.predict(plan, dict(robot, laser_resolution_deg=0.25))["trans_mean"]["value"]
    coarse = model.predict(plan, dict(robot, laser_resolution_deg=1.0))["trans_mean"]["value"]
    assert fine > 1.1 * coarse
    assert model.resolution_warning(0.25) is None
    warnings = model.domain_warnings(plan, dict(robot, laser_resolution_deg=0.1), 0.1)
    assert any(w.startswith("laser_resolution_deg = 0.1 deg is outside the training range")
               for w in warnings)


def test_the_report_plots_the_resolution_it_learnt(trained):
    """A partial-dependence panel for the resolution when the runs varied it (a model whose
    runs had one resolution gets none: tests/report/test_robot_report.py)."""
    from slam_predict.report.robot_models import curves

    lines = curves(RobotModel.load(trained[0]), "trans_mean")
    assert list(lines)[-1] == "laser_resolution_deg"
    assert lines["laser_resolution_deg"]["trained"] == [0.25, 1.0]


def test_brackets_weigh_the_two_trained_resolutions_around_a_laser_on_a_log_scale():
    from slam_predict.learn.robot.resolution import brackets

    assert brackets(RESOLUTIONS, 0.5) == [(0.5, 1.0)]
    assert brackets(RESOLUTIONS, 0.1) == [(0.1, 1.0)] and brackets(RESOLUTIONS, 2.0) == [(2.0, 1.0)]
    assert brackets([0.5], 0.35) == [(0.35, 1.0)]
    (low, a), (high, b) = brackets(RESOLUTIONS, 0.35)
    assert (low, high) == (0.25, 0.5) and a + b == pytest.approx(1.0)
    assert b == pytest.approx(np.log(0.35 / 0.25) / np.log(2.0))
    (_, a), (_, b) = brackets(RESOLUTIONS, 0.5 * 2 ** 0.5)      # log midpoint of 0.5 and 1
    assert a == pytest.approx(0.5) and b == pytest.approx(0.5)


def test_a_laser_between_trained_resolutions_reads_between_their_predictions(trained):
    """Trees step between the three trained resolutions; the prediction between two of them is
    their log-scale interpolation: at the log midpoint the geometric mean of both ends (value
    and bounds), and it moves smoothly across the span, never beyond its ends."""
    folder, worlds = trained
    model = RobotModel.load(folder)
    plan = dict(next(iter(worlds.values())))
    robot = {"laser_range_max_m": 12.0, "laser_fov_deg": 270.0, "odom_xy_error": 0.01,
             "odom_yaw_error": 0.035}
    at = {r: model.predict(plan, dict(robot, laser_resolution_deg=r))["trans_mean"]
          for r in (0.25, 0.5, 0.25 * 2 ** 0.5)}
    for key in ("value", "low", "high"):
        assert at[0.25 * 2 ** 0.5][key] == pytest.approx((at[0.25][key] * at[0.5][key]) ** 0.5)
    grid = np.geomspace(0.25, 0.5, 9)
    values = [model.predict(plan, dict(robot, laser_resolution_deg=r))["trans_mean"]["value"]
              for r in grid]
    assert values[0] == at[0.25]["value"] and values[-1] == at[0.5]["value"]
    steps = np.diff(np.log(values))
    assert np.all(np.sign(steps) == np.sign(steps[0])) and np.ptp(steps) < 1e-9
