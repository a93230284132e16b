"""The monotone check of the robot-aware models (learn/robot/monotone_check.py): it finds a
drop where one is planted and none in a monotone function, the shipping rule replaces a model
that fails it, and a GRID TEST over the robot inputs' box (training range and the
extrapolation beyond it) of the shipped ``own-robots``: no component, value or interval bound,
gets smaller when the robot gets worse, on every training building."""
from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
import pytest

from slam_predict.features.sightline import blind_fraction
from slam_predict.learn.dataset import COMPONENTS
from slam_predict.learn.robot.config import RobotLearningConfig
from slam_predict.learn.robot.inputs import ROBOT_INPUTS
from slam_predict.learn.robot.monotone_check import (
    MIN_RANGE_M,
    WORSE,
    grid_rows,
    monotone_violations,
    passes,
    robot_axes,
    worst_drops,
)
from slam_predict.learn.robot.predict import RobotModel
from slam_predict.learn.robot.train import monotone_best

NAMES = ["building_area", "laser_blind_fraction", *ROBOT_INPUTS]
RANGES = {"laser_range_max_m": [3.5, 30.0], "laser_fov_deg": [180.0, 360.0],
          "odom_xy_error": [0.0, 0.02], "odom_yaw_error": [0.0, 0.07]}


@dataclass
class Formula:
    """A LogScaleModel stand-in: value = f(X), interval = value × (0.5, 2)."""

    f: object
    component: str = "trans_mean"

    def predict(self, X):
        return self.f(np.atleast_2d(X))

    def interval(self, X, confidence=0.9, runs=2):
        value = self.predict(X)
        return np.column_stack([0.5 * value, 2.0 * value])


def _worse_robot(X):
    """An error that grows with a worse robot and with the blind fraction."""
    col = {n: X[:, NAMES.index(n)] for n in NAMES}
    return (1.0 + col["laser_blind_fraction"] + 10.0 / col["laser_range_max_m"]
            + 100.0 / col["laser_fov_deg"] + col["odom_xy_error"] + col["odom_yaw_error"])


def _planted(X):
    """As _worse_robot, but a wider fov makes it WORSE above 300°."""
    fov = X[:, NAMES.index("laser_fov_deg")]
    return _worse_robot(X) + 0.05 * np.maximum(fov - 300.0, 0.0)


def test_axes_run_from_the_best_robot_to_the_worst_and_beyond_the_box():
    axes = robot_axes(RANGES, 30.0, points=5)
    assert axes["laser_range_max_m"][0] == 30.0 and axes["laser_range_max_m"][-1] == MIN_RANGE_M
    assert axes["laser_fov_deg"][0] == 360.0 and axes["laser_fov_deg"][-1] == 10.0
    assert axes["odom_yaw_error"][0] == 0.0 and axes["odom_yaw_error"][-1] == pytest.approx(0.21)
    for name, values in axes.items():
        assert np.all(np.sign(np.diff(values)) == WORSE[name])


def test_worst_drops_measures_relative_drops_per_axis():
    values = np.ones((2, 3, 2, 2))
    assert worst_drops(values) == dict.fromkeys(ROBOT_INPUTS, 0.0)
    values[0, 2, 0, 0] = 0.75                  # the fov's last (worst) step drops
    drops = worst_drops(values)
    assert drops["laser_fov_deg"] == pytest.approx(0.25)
    assert drops["laser_range_max_m"] == 0.0 and drops["odom_xy_error"] == 0.0
    values[0, 2, 0, 0] = 1.5                   # a rise: the axes leaving it drop 1.5 → 1
    drops = worst_drops(values)
    assert drops["laser_fov_deg"] == 0.0
    assert drops["laser_range_max_m"] == pytest.approx(1 / 3)
    assert drops["odom_xy_error"] == pytest.approx(1 / 3)


def test_grid_rows_set_every_robot_combination_and_the_blind_fraction():
    axes = robot_axes(RANGES, 30.0, points=3)
    rows = grid_rows(np.array([500.0, -1.0, 0, 0, 0, 0]), NAMES, axes, lambda r: 1.0 / r)
    assert rows.shape == (*(len(axes[n]) for n in ROBOT_INPUTS), len(NAMES))
    assert np.all(rows[..., 0] == 500.0)
    i = 2
    assert np.all(rows[i, ..., 2] == axes["laser_range_max_m"][i])
    assert np.allclose(rows[i, ..., 1], 1.0 / axes["laser_range_max_m"][i])
    assert np.all(rows[:, 1, :, :, 3] == axes["laser_fov_deg"][1])


def test_the_check_finds_a_planted_violation_and_passes_a_monotone_model():
    axes = robot_axes(RANGES, 30.0, points=5)
    plans = np.array([[500.0, 0.0, 0, 0, 0, 0], [2000.0, 0.0, 0, 0, 0, 0]])
    blinds = [lambda r: 0.5 * np.exp(-r / 10.0), lambda r: 0.9 * np.exp(-r / 5.0)]
    good = monotone_violations(Formula(_worse_robot), NAMES, plans, blinds, axes)
    assert passes(good) and good == dict.fromkeys(ROBOT_INPUTS, 0.0)
    bad = monotone_violations(Formula(_planted), NAMES, plans, blinds, axes)
    assert not passes(bad) and bad["laser_fov_deg"] > 0.01
    assert [n for n in ROBOT_INPUTS if bad[n] > 0] == ["laser_fov_deg"]


def test_a_model_failing_the_check_is_replaced_by_the_best_passing_one():
    summary = [{"protocol": "both", "component": "rot_mean", "model": kind,
                "median_pct_error": pct, "r2": 0.2}
               for kind, pct in (("gaussian_process", 0.18), ("trend_boosting", 0.20),
                                 ("elasticnet", 0.21))]
    config = RobotLearningConfig()
    bad, good = {"laser_fov_deg": 0.2}, dict.fromkeys(ROBOT_INPUTS, 0.0)
    checks = {"rot_mean": {"gaussian_process": bad, "trend_boosting": good, "elasticnet": good}}
    assert monotone_best({"rot_mean": "gaussian_process"}, summary, config, checks) == {
        "rot_mean": "trend_boosting"}
    assert monotone_best({"rot_mean": "elasticnet"}, summary, config, checks) == {
        "rot_mean": "elasticnet"}                      # a passing choice is kept
    checks["rot_mean"] = {k: bad for k in checks["rot_mean"]}
    assert monotone_best({"rot_mean": "gaussian_process"}, summary, config, checks) == {
        "rot_mean": "gaussian_process"}                # nothing passes: kept (logged)
    checks = {"rot_mean": {"gaussian_process": bad, "elasticnet": good}}
    assert monotone_best({"rot_mean": "gaussian_process"}, [], config, checks) == {
        "rot_mean": "elasticnet"}                      # no evaluation: configuration order


@pytest.fixture(scope="module")
def shipped(root) -> RobotModel:
    return RobotModel.load(root / "models" / "own-robots")


def _plans(model: RobotModel):
    """One training POINT row and the blind-fraction function of every training building."""
    curves = model.card["sightline_curves"]
    worlds = sorted(set(model.point_worlds))
    rows = np.array([model.points[model.point_worlds.index(w)] for w in worlds])
    return worlds, rows, [lambda r, c=curves[w]: blind_fraction(c, r) for w in worlds]


@pytest.mark.parametrize("component", COMPONENTS)
def test_shipped_model_never_improves_when_the_robot_gets_worse(shipped, component):
    """GRID TEST: 7 values inside each robot input's training range plus the extrapolation
    (laser 0.1 m-maxUrange, fov 10-360°, odometry 0-3 × the training maximum), every
    combination, at each of the 21 training buildings: value and both interval bounds."""
    worlds, rows, blinds = _plans(shipped)
    assert len(worlds) >= 3
    axes = robot_axes(shipped.card["input_ranges"], shipped.max_urange_m, points=7)
    drops = monotone_violations(shipped.models[component], shipped.names, rows, blinds, axes,
                                float(shipped.card["confidence"]),
                                int(shipped.card["interval_runs"]))
    assert passes(drops), drops
    entry = shipped.card["components"][component]
    assert entry["models"][entry["best"]]["monotone"]["passed"]


def test_shipped_predict_path_is_monotone_in_each_robot_input(shipped):
    """Through RobotModel.predict (plan features → derived input → value and interval), on
    3 buildings, one robot input at a time from a mid-box robot, at the trained angular
    resolutions and between them (the prediction interpolated between two)."""
    worlds, rows, _ = _plans(shipped)
    curves = shipped.card["sightline_curves"]
    plan_names = [n for n in shipped.names if n not in ROBOT_INPUTS
                  and n not in ("laser_blind_fraction", "laser_resolution_deg")]
    from slam_predict.features.sightline import curve_columns

    axes = robot_axes(shipped.card["input_ranges"], shipped.max_urange_m, points=6)
    base = {n: float(np.mean(shipped.card["input_ranges"][n])) for n in ROBOT_INPUTS}
    for world, row in list(zip(worlds, rows, strict=True))[:3]:
        plan = {n: float(row[shipped.names.index(n)]) for n in plan_names}
        plan.update(dict(zip(curve_columns(), curves[world], strict=True)))
        for name, resolution in itertools.product(ROBOT_INPUTS, (0.25, 0.35, 0.5, 1.0)):
            robot = dict(base, laser_resolution_deg=resolution)
            out = [shipped.predict(plan, dict(robot, **{name: float(v)})) for v in axes[name]]
            for component in COMPONENTS:
                for key in ("value", "low", "high"):
                    series = np.array([o[component][key] for o in out])
                    assert np.all(np.diff(series) >= -1e-9 * series[:-1]), (
                        world, name, resolution, component, key)
