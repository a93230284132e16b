"""The rules over runs have one copy (slam_predict.metric.runs): the failed-exploration
coverage and the two stds over runs, checked against plain formulas."""
from __future__ import annotations

import inspect
import math

import numpy as np
import pytest

from slam_predict.cli import fidelity_cmd
from slam_predict.collect.fidelity import compare_campaign
from slam_predict.collect.summary import building_row
from slam_predict.learn.robot.agreement import agreement_rows
from slam_predict.learn.robot.config import RobotLearningConfig
from slam_predict.learn.robot.records import read_runs
from slam_predict.metric.runs import (
    BUILDING_STD_DDOF,
    MIN_COVERAGE,
    SAMPLE_STD_DDOF,
    building_statistics,
    sample_std,
)


def default_of(function, name: str):
    return inspect.signature(function).parameters[name].default


def test_every_min_coverage_default_is_the_one_rule():
    assert MIN_COVERAGE == 0.5
    assert default_of(compare_campaign, "min_coverage") == MIN_COVERAGE
    assert default_of(agreement_rows, "min_coverage") == MIN_COVERAGE
    assert default_of(read_runs, "min_coverage") == MIN_COVERAGE
    assert RobotLearningConfig().min_coverage == MIN_COVERAGE
    import argparse
    parser = argparse.ArgumentParser()
    fidelity_cmd.add_arguments(parser)
    assert parser.parse_args(["DATA", "--thesis", "T.csv"]).min_coverage == MIN_COVERAGE


def population_std(values):
    mean = sum(values) / len(values)
    return math.sqrt(sum((v - mean) ** 2 for v in values) / len(values))


def corrected_std(values):
    mean = sum(values) / len(values)
    return math.sqrt(sum((v - mean) ** 2 for v in values) / (len(values) - 1))


def test_the_two_stds_over_runs_are_the_plain_formulas():
    assert (BUILDING_STD_DDOF, SAMPLE_STD_DDOF) == (0, 1)
    rng = np.random.default_rng(3)
    trans, rot = rng.uniform(0.1, 0.5, 5).tolist(), rng.uniform(0.01, 0.05, 5).tolist()
    stats = building_statistics(trans, rot)
    assert stats.trans_std == pytest.approx(population_std(trans), rel=1e-12)
    assert stats.rot_std == pytest.approx(population_std(rot), rel=1e-12)
    assert sample_std(trans) == pytest.approx(corrected_std(trans), rel=1e-12)
    assert math.isnan(sample_std(trans[:1]))


def test_summary_rows_use_the_building_std():
    rng = np.random.default_rng(4)
    trans, rot = rng.uniform(0.1, 0.5, 4), rng.uniform(0.01, 0.05, 4)
    records = [{"metric": {"trans_mean": t, "rot_mean": r, "trans_sqr_mean": t * t,
                           "rot_sqr_mean": r * r},
                "distance_m": 10.0, "rotation_rad": 1.0, "coverage": 0.9,
                "sim_duration_s": 100.0} for t, r in zip(trans, rot, strict=True)]
    row = building_row("w", records)
    assert row["trans_std"] == pytest.approx(population_std(trans.tolist()), rel=1e-12)
    assert row["rot_std"] == pytest.approx(population_std(rot.tolist()), rel=1e-12)
