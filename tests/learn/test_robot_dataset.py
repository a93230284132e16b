"""RUN and POINT tables of a campaign: against a hand computation, skips and bad inputs."""
from __future__ import annotations

import json
import logging
import math
from collections import defaultdict

import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.learn.dataset import to_csv_text
from slam_predict.learn.robot.inputs import ROBOT_INPUTS
from slam_predict.learn.robot.records import read_runs
from slam_predict.learn.robot.rundata import build_run_data, plan_features, runs_csv
from slam_predict.sensor import sensor_hash

from . import robot_synthetic as syn


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    folder = tmp_path_factory.mktemp("campaign")
    worlds, robots, records = syn.campaign(folder / "data")
    return folder, worlds, robots, records


def test_tables_match_a_hand_computation(campaign):
    folder, worlds, robots, records = campaign
    data = syn.load(folder / "data", worlds)
    points = data.point_dataset()
    assert len(data.runs) == 144 and len(points) == 72 and data.skipped == {}
    assert data.worlds == sorted(worlds) and list(data.configs) == [f"c{i:02d}" for i in range(6)]
    assert set(points.setting) == {"robots"} and set(points.slam) == {"gmapping"}
    by_point = defaultdict(list)
    for rec in records:
        by_point[rec["design"]["point"]].append(rec["metric"])
    for i, (world, config) in enumerate(zip(points.worlds, points.robot, strict=True)):
        metrics = by_point[f"{world}/{config}"]
        assert points.runs[i] == 2
        for name in ("trans_mean", "rot_mean"):
            a, b = (m[name] for m in metrics)
            assert points.target(name)[i] == pytest.approx((a + b) / 2, rel=1e-12)
            std = name.replace("mean", "std")
            assert points.target(std)[i] == pytest.approx(abs(a - b) / math.sqrt(2),
                                                          rel=1e-12)
    robot = robots[3]
    row = next(r for r in data.runs if r.config == "c03")
    assert row.robot["laser_range_max_m"] == robot["range_max"]
    assert row.robot["laser_fov_deg"] == pytest.approx(robot["fov"], rel=1e-12)
    assert row.robot["odom_xy_error"] == robot["xy"] and row.robot["odom_yaw_error"] == robot["yaw"]
    assert data.resolutions_deg == [0.5]
    assert {r.replicate for r in data.runs} == {0, 1}


def test_pooled_campaigns_of_one_design_get_unique_replicates(campaign, tmp_path):
    """A second campaign of the same design (another --seed: here a copy, reseeded) repeats the
    design's replicate numbers; pooled, each point's runs are numbered 0..n-1, and the runs of
    the first folder (by path) keep theirs."""
    import shutil

    folder = campaign[0]
    shutil.copytree(folder / "data", tmp_path / "more")
    for path in (tmp_path / "more").rglob("run.json"):       # the other campaign's seeds
        record = json.loads(path.read_text())
        record["seed"] += 1000
        path.write_text(json.dumps(record))
    first, _ = read_runs([folder / "data"])
    pooled, _ = read_runs([folder / "data", tmp_path / "more"])
    assert len(pooled) == 2 * len(first)
    by_point: dict[str, list] = defaultdict(list)
    for row in pooled:
        by_point[row.point].append(row)
    assert all(sorted(r.replicate for r in rows) == [0, 1, 2, 3] for rows in by_point.values())
    kept = {(r.source, r.replicate) for r in first}
    assert kept == {(r.source, r.replicate) for r in pooled if r.source.startswith(
        str(folder / "data"))}


def test_numeric_tables_and_subsets(campaign):
    folder, worlds, _, _ = campaign
    data = syn.load(folder / "data", worlds)
    tables = data.tables(["building_area"])
    assert tables.names[0] == "building_area" and tables.run_X.shape == (144, 5)
    assert np.all(tables.point_X[tables.run_point] == tables.run_X)
    rows = np.flatnonzero(tables.point_world == "w03")
    sub = tables.subset(rows)
    assert len(sub.point_X) == 6 and len(sub.run_X) == 12 and set(sub.run_world) == {"w03"}
    assert np.all(sub.point_X[sub.run_point] == sub.run_X)
    assert runs_csv(data).splitlines()[0].startswith("world,run_index,seed,config,point")
    header = to_csv_text(data.point_dataset(["building_area"])).splitlines()[0]
    assert header.endswith("rot_std," + ",".join(ROBOT_INPUTS) + ",building_area")


def test_runs_without_design_skips_and_missing_features(tmp_path, caplog):
    rng = np.random.default_rng(5)
    worlds = syn.buildings(3, rng)
    robots = syn.robot_configs(2, rng)
    records = syn.write_campaign(tmp_path, worlds, robots, 2, rng, design=False)
    low = json.loads(open(records[0]["path"]).read())
    low["coverage"] = 0.35                 # a failed exploration (< MIN_COVERAGE)
    open(records[0]["path"], "w").write(json.dumps(low))
    bare = json.loads(open(records[1]["path"]).read())
    del bare["metric"]
    open(records[1]["path"], "w").write(json.dumps(bare))
    with caplog.at_level(logging.WARNING):
        runs, skipped = read_runs([tmp_path])
    assert skipped == {"low coverage": 1, "no metric": 1} and len(runs) == 10
    assert "skipped 1 run: low coverage (< 0.5)" in caplog.text
    config = sensor_hash(syn.sensor(robots[1]))
    mine = [r for r in runs if r.world == "w00" and r.config == config]
    assert [r.point for r in mine] == [f"w00/{config}"] * 2
    assert sorted(r.replicate for r in mine) == [0, 1]
    features = {w: v for w, v in worlds.items() if w != "w02"}
    with caplog.at_level(logging.WARNING):
        data = build_run_data(runs, skipped, features, "v1")
    assert data.worlds == ["w00", "w01"] and data.skipped["no plan features"] == 4
    assert "1 building without plan features left out: w02" in caplog.text
    with pytest.raises(InputError, match="'building_aera' is not in the feature table "
                                         r"\(did you mean 'building_area'\?\)"):
        data.tables(["building_aera"])
    for name in ("sightline_isotropy", "floor_elongation"):
        with pytest.raises(InputError, match=f"'{name}' is not in the feature table "
                                             r"\(a sight-line feature: compute the features "
                                             "with --worlds\\)"):
            data.tables([name])


def edit(path, change):
    record = json.loads(open(path).read())
    change(record)
    open(path, "w").write(json.dumps(record))


@pytest.mark.parametrize("change, message", [
    (lambda r: r.pop("sensor"), "run record has no 'sensor'"),
    (lambda r: r.update(design={"config": "c00", "point": "w00/c00"}),
     "'design' has no 'replicate'"),
    (lambda r: r.update(coverage="most"), "'coverage' must be a finite number"),
    (lambda r: r.update(run_index=1.5), "'run_index' must be an integer"),
    (lambda r: r["sensor"]["laser"].update(fov=3.0),
     "configuration 'c00' has other robot inputs than in"),
    (lambda r: r["sensor"]["laser"].update(range_max=12.0),
     "settings file config/collect.yaml gives GMapping config .* for the run's 12 m laser, "
     "the run recorded"),
    (lambda r: r.pop("settings_file"), "names no settings_file or GMapping config hash"),
    (lambda r: r.update(settings_file="config/nope.yaml"),
     "settings file config/nope.yaml of the run not found"),
    (lambda r: r["design"].update(point="w01/c00"), "point 'w01/c00' is w0. × c00 here but"),
    (lambda r: r["sensor"]["odom"].update(model="fixed"),
     "runs mix odometry models .*uniform_per_run in .*: their error numbers describe"),
])
def test_bad_records_are_one_line_errors_naming_the_file(tmp_path, change, message):
    rng = np.random.default_rng(1)
    records = syn.write_campaign(tmp_path, syn.buildings(2, rng), syn.robot_configs(2, rng), 2,
                                 rng)
    target = records[1]["path"]
    edit(target, change)
    with pytest.raises(InputError, match=message) as err:
        read_runs([tmp_path])
    assert target in err.value.one_line() and "\n" not in err.value.one_line()


def test_runs_of_another_slam_algorithm_are_left_out_and_counted(tmp_path):
    rng = np.random.default_rng(1)
    records = syn.write_campaign(tmp_path, syn.buildings(2, rng), syn.robot_configs(2, rng), 2,
                                 rng)
    everything, _ = read_runs([tmp_path])
    edit(records[1]["path"], lambda r: r.update(slam={"type": "karto", "params_hash": "k"}))
    runs, skipped = read_runs([tmp_path])
    assert skipped == {"SLAM karto": 1} and len(runs) == len(everything) - 1
    assert {r.slam for r in runs} == {"gmapping"}
    assert records[1]["path"] not in {r.source for r in runs}
    # the karto run alone: its range cap comes from its settings file's Karto parameters, and
    # this one names a GMapping settings file (learn/robot/domain)
    with pytest.raises(InputError,
                       match="runs SLAM back-end 'gmapping' but the run ran 'karto'") as err:
        read_runs([tmp_path], slam="karto")
    assert records[1]["path"] in err.value.one_line()
    with pytest.raises(InputError, match="unknown SLAM algorithm 'cartographer'"):
        read_runs([tmp_path], slam="cartographer")


def test_unreadable_missing_and_empty_campaigns(tmp_path):
    with pytest.raises(InputError, match="campaign folder not found"):
        read_runs([tmp_path / "nope"])
    (tmp_path / "empty").mkdir()
    with pytest.raises(InputError, match="no run.json found"):
        read_runs([tmp_path / "empty"])
    bad = tmp_path / "bad" / "w00" / "run_000" / "run.json"
    bad.parent.mkdir(parents=True)
    bad.write_text("{not json")
    with pytest.raises(InputError, match="unreadable run record") as err:
        read_runs([tmp_path / "bad"])
    assert str(bad) in err.value.one_line()


def test_a_campaign_listed_twice_is_refused(campaign):
    folder = campaign[0] / "data"
    with pytest.raises(InputError, match="run listed twice"):
        read_runs([folder, folder])


def test_feature_table_needs_a_version(tmp_path, campaign):
    worlds = campaign[1]
    table = syn.write_features(tmp_path / "f.csv", worlds)
    features, version, config = plan_features(sorted(worlds), table)
    assert version == "synthetic-v1" and config == {} and "feature_version" not in features["w00"]
    text = table.read_text().replace("synthetic-v1", "")
    (tmp_path / "g.csv").write_text(text)
    with pytest.raises(InputError, match="needs one feature_version"):
        plan_features(sorted(worlds), tmp_path / "g.csv")
    assert plan_features(sorted(worlds), tmp_path / "g.csv", feature_version="v9")[1] == "v9"


def test_a_fixed_bias_campaign_is_learned_and_its_model_recorded(tmp_path):
    """Stage's fixed biases (the fidelity campaign's odometry) are robot inputs like bounds,
    with the same numbers; the dataset reports the model (the card records it)."""
    rng = np.random.default_rng(2)
    worlds = syn.buildings(2, rng)
    records = syn.write_campaign(tmp_path, worlds, syn.robot_configs(2, rng), 2, rng)
    bounds = syn.load(tmp_path, worlds)
    assert bounds.odom_model == "uniform_per_run"
    for item in records:
        edit(item["path"], lambda r: r["sensor"]["odom"].update(model="fixed"))
    biases = syn.load(tmp_path, worlds)
    assert {r.odom_model for r in biases.runs} == {"fixed"} and biases.odom_model == "fixed"
    assert [r.robot for r in biases.runs] == [r.robot for r in bounds.runs]


def test_plan_features_from_worlds_add_the_sightline_curve(tmp_path):
    """--worlds: each plan's features and its sight-line curve, from one load of the plan."""
    from pathlib import Path

    from slam_predict.features.plan import compute, full_feature_config
    from slam_predict.features.sightline import curve_columns, sightline_features
    from slam_predict.world.load import load_plan

    shipped = Path(__file__).resolve().parents[2] / "worlds"
    for suffix in (".world", ".png", ".json"):
        (tmp_path / f"office_150{suffix}").write_bytes(
            (shipped / f"office_150{suffix}").read_bytes())
    features, version, config = plan_features(["office_150"], worlds_dir=tmp_path)
    plan = load_plan(tmp_path / "office_150.world")
    expected = dict(compute(plan, full_feature_config(None)), **sightline_features(plan))
    assert features["office_150"] == pytest.approx(expected, rel=1e-12)
    assert set(curve_columns()) <= set(features["office_150"])
    assert version.startswith("2+") and config == full_feature_config(None)
