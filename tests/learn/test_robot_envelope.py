"""Robot-aware predictions never improve when the robot gets worse (learn/robot/envelope.py)."""
from __future__ import annotations

import csv
import itertools

import numpy as np
import pytest

from slam_predict.features.sightline import curve_columns
from slam_predict.learn.robot import envelope
from slam_predict.learn.robot.predict import RobotModel

COMPONENTS = ("trans_mean", "trans_std", "rot_mean", "rot_std")


def brute_force_envelope(values: np.ndarray) -> np.ndarray:
    """Each node's maximum over every node at least as good on all axes (index ≤ on each)."""
    out = np.empty_like(values)
    for index in itertools.product(*(range(n) for n in values.shape)):
        better = tuple(slice(0, i + 1) for i in index)
        out[index] = values[better].max()
    return out


def test_envelope_is_the_maximum_over_every_better_node():
    rng = np.random.default_rng(0)
    values = rng.normal(size=(4, 3, 5, 2))
    assert np.array_equal(envelope.envelope(values), brute_force_envelope(values))


def test_interpolation_hits_the_nodes_and_is_linear_between_them():
    axes = {"a": np.array([30.0, 10.0, 1.0]), "b": np.array([0.0, 1.0])}
    grid = np.array([[0.0, 1.0], [2.0, 3.0], [4.0, 7.0]])
    assert envelope.interpolate(grid, axes, {"a": 10.0, "b": 1.0}) == 3.0
    assert envelope.interpolate(grid, axes, {"a": 20.0, "b": 0.5}) == pytest.approx(1.5)
    assert envelope.interpolate(grid, axes, {"a": 99.0, "b": -4.0}) == 0.0   # clamped


@pytest.fixture(scope="module")
def model(root) -> RobotModel:
    return RobotModel.load(root / "models" / "own-robots")


def plans(root, model, count=3):
    """Plan feature dicts (with their sight-line curves) of ``count`` training buildings."""
    with open(root / "models" / "own-robots" / "training_points.csv", newline="") as handle:
        rows = {r["world"]: r for r in csv.DictReader(handle)}
    out = []
    for world in sorted(rows)[:: max(1, len(rows) // count)][:count]:
        features = {n: float(rows[world][n]) for n in model.card["features"]}
        features.update(zip(curve_columns(), model.card["sightline_curves"][world],
                            strict=True))
        out.append(features)
    return out


def robot_grid():
    """Robots over and beyond the training box: range m, fov deg, odometry xy, yaw."""
    return list(itertools.product([0.5, 8.0, 30.0], [90.0, 240.0, 360.0], [0.0, 0.05],
                                  [0.0, 0.1]))


def test_no_component_improves_when_the_robot_gets_worse(root, model):
    names = ("laser_range_max_m", "laser_fov_deg", "odom_xy_error", "odom_yaw_error",
             "laser_resolution_deg")
    grid = robot_grid()
    for features, resolution in itertools.product(plans(root, model), (0.25, 0.35, 1.0)):
        pred = {q: model.predict(features, dict(zip(names, (*q, resolution), strict=True)))
                for q in grid}
        for good, bad in itertools.product(grid, grid):
            worse = (bad[0] <= good[0] and bad[1] <= good[1] and bad[2] >= good[2]
                     and bad[3] >= good[3])
            if not worse or good == bad:
                continue
            for c in COMPONENTS:
                for key in ("value", "low", "high"):
                    assert pred[bad][c][key] >= pred[good][c][key] - 1e-12, (c, key, good, bad)
