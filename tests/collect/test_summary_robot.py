"""summary.csv and the learning dataset keyed by (world, robot configuration hash); committed
campaigns, written before run.json recorded the sensor, give the same rows as before."""
import csv
import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from slam_predict.collect.summary import COLUMNS, write_summary
from slam_predict.config import to_dict
from slam_predict.learn import dataset as ds
from slam_predict.learn import sources
from slam_predict.sensor import LaserConfig, SensorConfig, sensor_hash

ROOT = Path(__file__).resolve().parents[2]
REALISTIC = ROOT / "data" / "campaigns" / "realistic"
SEED_LASER = SensorConfig()
SMALL_LASER = SensorConfig(laser=LaserConfig(fov=2 * math.pi, samples=360, range_max=3.5))


def _record(world, index, trans, sensor=None):
    record = {"world": world, "run_index": index,
              "metric": {"trans_mean": trans, "rot_mean": trans / 10, "trans_sqr_mean": trans ** 2,
                         "rot_sqr_mean": trans ** 2 / 100},
              "distance_m": 50.0 + index, "rotation_rad": 20.0, "coverage": 0.9,
              "sim_duration_s": 600.0}
    if sensor is not None:
        record["sensor"] = to_dict(sensor)
    return record


def _write(root: Path, records):
    for index, record in enumerate(records):
        folder = root / record["world"] / f"run_{index:03d}"
        folder.mkdir(parents=True)
        (folder / "run.json").write_text(json.dumps(record))


def _rows(path: Path):
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def test_two_robots_in_one_world_give_two_rows(tmp_path):
    _write(tmp_path, [_record("a", 0, 0.1, SEED_LASER), _record("a", 1, 0.3, SEED_LASER),
                      _record("a", 2, 0.5, SMALL_LASER), _record("a", 3, 0.9, SMALL_LASER),
                      _record("b", 0, 0.2), _record("b", 1, 0.4)])
    rows = _rows(write_summary(tmp_path))
    keys = [(row["world"], row["robot"]) for row in rows]
    expected_a = sorted([sensor_hash(SEED_LASER), sensor_hash(SMALL_LASER)])
    assert keys == [("a", expected_a[0]), ("a", expected_a[1]), ("b", "")]
    trans = {row["robot"]: float(row["trans_mean"]) for row in rows if row["world"] == "a"}
    assert trans[sensor_hash(SEED_LASER)] == pytest.approx(0.2)
    assert trans[sensor_hash(SMALL_LASER)] == pytest.approx(0.7)
    assert [row["runs"] for row in rows] == ["2", "2", "2"]

    errors = sources.read_error_table(tmp_path / "summary.csv", "realistic")
    assert [(e.world, e.robot) for e in errors] == keys
    features = {"a": {"area": 1.0}, "b": {"area": 2.0}}
    data = ds.join(errors, features, "v")
    assert data.robot == [k[1] for k in keys] and data.X[:, 0].tolist() == [1.0, 1.0, 2.0]
    ds.write_dataset(data, tmp_path / "data.csv")
    again = ds.read_dataset(tmp_path / "data.csv")
    assert again.robot == data.robot and np.array_equal(again.Y, data.Y)
    assert again.subset([1]).robot == [data.robot[1]]


def test_a_world_listed_twice_with_one_robot_is_refused(tmp_path):
    path = tmp_path / "summary.csv"
    path.write_text("world,robot,trans_mean,trans_std,rot_mean,rot_std\n"
                    "a,h1,1,1,1,1\na,h2,1,1,1,1\na,h1,1,1,1,1\n")
    with pytest.raises(ds.InputError, match="'a' with robot h1 appears twice"):
        sources.read_error_table(path)


def test_committed_campaign_gives_the_committed_summary(tmp_path):
    """The realistic campaign's run records (no ``sensor`` key) give its summary.csv again,
    column for column, with an empty robot key; the dataset reads the committed CSV."""
    for run_json in REALISTIC.glob("*/run_*/run.json"):
        target = tmp_path / run_json.relative_to(REALISTIC)
        target.parent.mkdir(parents=True)
        shutil.copy(run_json, target)
    committed = _rows(REALISTIC / "summary.csv")
    regenerated = _rows(write_summary(tmp_path))
    assert len(regenerated) == len(committed) > 5
    for old, new in zip(committed, regenerated, strict=True):
        assert new["robot"] == ""
        assert {k: new[k] for k in COLUMNS if k != "robot"} == old
    rows = sources.read_error_table(REALISTIC / "summary.csv")
    assert [r.world for r in rows] == [row["world"] for row in committed]
    assert all(r.robot == "" for r in rows)


def test_runs_without_a_metric_are_left_out_of_the_summary(tmp_path):
    """A run whose robot never moved (``metric: null``) adds no error and counts no run; a world
    with only such runs gets no row."""
    still = {**_record("a", 2, 0.0), "metric": None, "metric_note": "never moved"}
    only_still = {**_record("b", 0, 0.0), "metric": None, "metric_note": "never moved"}
    _write(tmp_path, [_record("a", 0, 0.1), _record("a", 1, 0.3), still, only_still])
    rows = _rows(write_summary(tmp_path))
    assert [(row["world"], row["runs"]) for row in rows] == [("a", "2")]
    assert float(rows[0]["trans_mean"]) == pytest.approx(0.2)
