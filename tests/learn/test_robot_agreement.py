"""agreement_rows: a model's predictions beside a campaign's measured means per building."""
from __future__ import annotations

import json

import pytest

from slam_predict.learn.robot.agreement import agreement_rows, error_bars


def scale_features(plan):
    return {"scale": plan}


class FixedModel:
    """Predicts the plan's 'scale' times the robot's 'gain' (m and rad)."""

    card = {"training_buildings": ["a"]}

    def predict(self, features, robot):
        value = features["scale"] * robot["gain"]
        return {"trans_mean": {"value": value}, "rot_mean": {"value": value / 10}}


def write_run(root, world, index, coverage, trans, rot, area=100.0):
    folder = root / world / f"run_{index:03d}"
    folder.mkdir(parents=True)
    record = {"coverage": coverage, "free_area_m2": area,
              "metric": {"trans_mean": trans, "rot_mean": rot}}
    (folder / "run.json").write_text(json.dumps(record))


@pytest.fixture()
def campaign(tmp_path):
    write_run(tmp_path, "a", 0, 0.9, 1.0, 0.1, area=100.0)
    write_run(tmp_path, "a", 1, 0.8, 3.0, 0.3, area=120.0)
    write_run(tmp_path, "a", 2, 0.2, 50.0, 5.0)            # failed exploration: left out
    write_run(tmp_path, "b", 0, 0.9, 2.0, 0.2)
    write_run(tmp_path, "c", 0, 0.1, 2.0, 0.2)             # no usable run: no row
    write_run(tmp_path, "d", 0, 0.9, 2.0, 0.2)             # no plan: no row
    return tmp_path


def test_rows_hold_predictions_and_means_of_usable_runs(campaign):
    plans = {"a": 2.0, "b": 4.0, "c": 1.0}
    rows = agreement_rows(FixedModel(), {"gain": 0.5}, campaign, plans.get,
                          features_of=scale_features)
    assert [r["world"] for r in rows] == ["a", "b"]
    a = rows[0]
    assert a["runs"] == 2 and a["trained_on"] and a["free_area_m2"] == pytest.approx(110.0)
    assert a["trans_mean_ours"] == pytest.approx(1.0) and a["trans_mean_theirs"] == 2.0
    assert a["rot_mean_ours"] == pytest.approx(0.1) and a["rot_mean_theirs"] == pytest.approx(0.2)
    assert not rows[1]["trained_on"] and rows[1]["trans_mean_ours"] == pytest.approx(2.0)


def test_unseen_and_coverage_filters(campaign):
    plans = {"a": 2.0, "b": 4.0, "c": 1.0}
    assert [r["world"] for r in agreement_rows(FixedModel(), {"gain": 1.0}, campaign,
                                               plans.get, unseen=True,
                                               features_of=scale_features)] == ["b"]
    rows = agreement_rows(FixedModel(), {"gain": 1.0}, campaign, plans.get, min_coverage=0.0,
                          features_of=scale_features)
    assert [r["runs"] for r in rows] == [3, 1, 1]


def test_error_bars_leave_out_path_length():
    labels = [bar.figure for bar in error_bars()]
    assert labels and not any("path_length" in f for f in labels)
