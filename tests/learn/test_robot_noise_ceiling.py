"""replicate_r2_ceiling: the R² that run-to-run noise leaves to a perfect model."""
from __future__ import annotations

import numpy as np
import pytest

from slam_predict.learn.robot.evaluate import replicate_r2_ceiling
from slam_predict.learn.robot.rundata import RobotTables


def tables_of(runs_per_point: list[list[float]]) -> RobotTables:
    """Tables with one input column and the given run errors (m) per point."""
    values = np.array([v for runs in runs_per_point for v in runs], dtype=float)
    run_point = np.repeat(np.arange(len(runs_per_point)), [len(r) for r in runs_per_point])
    n = len(runs_per_point)
    means = np.array([np.mean(r) for r in runs_per_point])
    stds = np.array([np.std(r, ddof=1) if len(r) > 1 else np.nan for r in runs_per_point])
    return RobotTables(
        names=["x"], run_X=np.zeros((len(values), 1)), run_y={"trans_mean": values,
                                                             "rot_mean": values / 10},
        run_point=run_point, point_X=np.zeros((n, 1)),
        point_y={"trans_mean": means, "rot_mean": means / 10, "trans_std": stds,
                 "rot_std": stds / 10},
        point_runs=np.array([len(r) for r in runs_per_point]),
        point_world=np.array([f"w{i}" for i in range(n)]),
        point_config=np.array(["c"] * n))


def test_ceiling_by_hand():
    # noise s²/n: 1, 0, 1; point means 2, 5, 10 (sum of squares 32.667); one-run point ignored
    tables = tables_of([[1.0, 3.0], [5.0, 5.0], [9.0, 11.0], [100.0]])
    ceiling, n = replicate_r2_ceiling(tables, "trans_mean")
    assert n == 3 and ceiling == pytest.approx(1.0 - 2.0 / (32.0 + 2.0 / 3.0))
    assert replicate_r2_ceiling(tables, "rot_mean")[0] == pytest.approx(ceiling)


def test_too_few_replicated_points_give_nan():
    ceiling, n = replicate_r2_ceiling(tables_of([[1.0, 2.0], [3.0, 4.0], [5.0]]), "trans_mean")
    assert np.isnan(ceiling) and n == 2


def test_ceiling_matches_the_r2_of_exact_means_in_simulation():
    """Many simulated campaigns: the ceiling estimate averages to the R² that the true
    means actually score against the measured 2-run means."""
    rng = np.random.default_rng(5)
    estimates, actual = [], []
    for _ in range(400):
        truth = rng.uniform(0.5, 3.0, 40)
        sigma = 0.3 * truth
        runs = [list(m + s * rng.standard_normal(2)) for m, s in zip(truth, sigma, strict=True)]
        measured = np.array([np.mean(r) for r in runs])
        estimates.append(replicate_r2_ceiling(tables_of(runs), "trans_mean")[0])
        actual.append(1 - np.sum((measured - truth) ** 2)
                      / np.sum((measured - measured.mean()) ** 2))
    assert np.mean(estimates) == pytest.approx(np.mean(actual), abs=0.01)
    assert 0.7 < np.mean(actual) < 0.95     # the simulation is in the interesting range
