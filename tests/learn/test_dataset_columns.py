"""The one dataset format: optional robot and slam columns, the slam filter, old POINT files,
the SLAM algorithm of a collection summary, and ``learn train --slam``."""
from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

from slam_predict.cli.main import main
from slam_predict.errors import InputError
from slam_predict.learn import dataset as ds
from slam_predict.learn import sources
from slam_predict.learn.robot.inputs import ROBOT_INPUTS

from .conftest import synthetic_dataset

ROOT = Path(__file__).resolve().parents[2]
# header and three rows of models/own-robots/training_points.csv as shipped 2026-12-05
OLD_POINTS = (
    "world,config,point,runs,laser_range_max_m,laser_fov_deg,odom_xy_error"
    ",odom_yaw_error,trans_mean,trans_std,rot_mean,rot_std,building_area"
    ",sightline_isotropy,voronoi_traversal_distance,floor_elongation"
    ",laser_blind_fraction\n"
    "324-Elm-Furn-Plan_updated,c02,324-Elm-Furn-Plan_updated/c02,4,15.7918,215.7625"
    ",0.004762000000000001,0.03328691949403585,0.6347231693074796,0.1288843352893546"
    ",0.03810392110097656,0.010179130274287468,1288.7900000000002,0.6551254153469059"
    ",737.2250616357753,3.9390164613603047,0.0027416057973151196\n"
    "324-Elm-Furn-Plan_updated,c04,324-Elm-Furn-Plan_updated/c04,3,4.3001,238.4068"
    ",0.012462,0.008011061266653973,2.734293557969952,0.903264795311686"
    ",0.04253414571281653,0.013979117339636438,1288.7900000000002,0.6551254153469059"
    ",737.2250616357753,3.9390164613603047,0.2835908362578996\n"
    "324-Elm-Furn-Plan_updated,c12,324-Elm-Furn-Plan_updated/c12,4,23.922,313.8874"
    ",0.0055769999999999995,0.029848620867607024,0.4991983553713534"
    ",0.02867889883660824,0.028171228952051423,0.002216396638060137"
    ",1288.7900000000002,0.6551254153469059,737.2250616357753,3.9390164613603047"
    ",0.0010000000000000002\n"
)


def _rows(names, slams=None):
    slams = slams or ["gmapping"] * len(names)
    return [ds.ErrorRow(n, {c: float(i + 1) for c in ds.COMPONENTS}, runs=i + 3,
                        setting="realistic", slam_config_hash="h", robot=f"r{i}", slam=slam)
            for i, (n, slam) in enumerate(zip(names, slams, strict=True))]


def _features(names):
    return {n: {"x": i * 0.1 + 1e-12, "y": -float(i)} for i, n in enumerate(names)}


def _same(back: ds.Dataset, data: ds.Dataset) -> None:
    assert back.worlds == data.worlds and back.feature_names == data.feature_names
    assert back.robot == data.robot and back.slam == data.slam
    np.testing.assert_array_equal(back.X, data.X)
    np.testing.assert_array_equal(back.Y, data.Y)
    np.testing.assert_array_equal(back.runs, data.runs)
    assert sorted(back.robot_inputs) == sorted(data.robot_inputs)
    for name, values in data.robot_inputs.items():
        np.testing.assert_array_equal(back.robot_inputs[name], values)


def test_round_trip_without_robot_and_slam_columns(tmp_path):
    data = ds.join(_rows(["a", "b", "c"]), _features("abc"), "v1")
    ds.write_dataset(data, tmp_path / "d.csv")
    header = (tmp_path / "d.csv").read_text().splitlines()[0].split(",")
    assert "slam" not in header and not set(ROBOT_INPUTS) & set(header)
    back = ds.read_dataset(tmp_path / "d.csv")
    _same(back, data)
    assert back.slam == ["gmapping"] * 3 and back.robot_inputs == {}


def test_round_trip_with_robot_and_slam_columns(tmp_path):
    data = ds.join(_rows(["a", "b", "c"], ["gmapping", "karto", "karto"]), _features("abc"), "v1")
    rng = np.random.default_rng(3)
    data.robot_inputs = {name: rng.uniform(0.001, 30.0, 3) for name in ROBOT_INPUTS}
    data.Y[1, ds.component_index("rot_std")] = math.nan          # a POINT row of one run
    ds.write_dataset(data, tmp_path / "d.csv")
    with open(tmp_path / "d.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert [r["slam"] for r in rows] == ["gmapping", "karto", "karto"]
    assert rows[1]["rot_std"] == "" and float(rows[0]["laser_fov_deg"]) == \
        data.robot_inputs["laser_fov_deg"][0]
    back = ds.read_dataset(tmp_path / "d.csv")
    _same(back, data)
    assert back.feature_names == ["x", "y"]            # robot columns are not features
    assert np.isnan(back.target("rot_std")[1])


def test_a_missing_mean_or_an_unknown_slam_is_refused(tmp_path):
    data = ds.join(_rows(["a", "b"], ["gmapping", "karto"]), _features("ab"), "v1")
    text = ds.to_csv_text(data)
    (tmp_path / "bad.csv").write_text(text.replace(",karto,", ",kartoo,"))
    with pytest.raises(InputError, match=r"bad.csv:3: unknown SLAM algorithm 'kartoo'"):
        ds.read_dataset(tmp_path / "bad.csv")
    lines = text.splitlines()
    header = lines[0].split(",")
    cells = lines[1].split(",")
    cells[header.index("trans_mean")] = ""
    (tmp_path / "empty.csv").write_text("\n".join([lines[0], ",".join(cells), lines[2]]) + "\n")
    with pytest.raises(InputError, match="column 'trans_mean' is not a number"):
        ds.read_dataset(tmp_path / "empty.csv")


def test_select_slam_keeps_the_rows_of_one_algorithm():
    data = ds.join(_rows(["a", "b", "c"], ["karto", "gmapping", "karto"]), _features("abc"),
                   "v1")
    karto = data.select_slam("karto")
    assert karto.worlds == ["a", "c"] and karto.unique("slam") == "karto"
    np.testing.assert_array_equal(karto.X, data.X[[0, 2]])
    assert data.select_slam().worlds == ["b"]
    only = data.subset([0, 2])
    with pytest.raises(InputError, match="no rows of SLAM algorithm 'gmapping' .*karto"):
        only.select_slam("gmapping")
    with pytest.raises(InputError, match="did you mean 'karto'"):
        data.select_slam("kartoo")


def test_an_old_point_file_reads_as_the_dataset(tmp_path):
    """training_points.csv of models/own-robots before 2026-12-06 predates the format (config,
    point columns): read_dataset gives the same numbers as a plain CSV parse."""
    path = tmp_path / "training_points.csv"
    path.write_text(OLD_POINTS)
    with open(path, newline="") as handle:
        rows = list(csv.DictReader(handle))
    data = ds.read_dataset(path)
    assert len(rows) == 3 and data.worlds == [r["world"] for r in rows]
    assert data.robot == [r["config"] for r in rows] and set(data.slam) == {"gmapping"}
    assert sorted(data.robot_inputs) == sorted(ROBOT_INPUTS)
    assert "point" not in data.feature_names and "config" not in data.feature_names
    names = [*data.feature_names, *ROBOT_INPUTS]
    expected = np.array([[float(r[n]) for n in names] for r in rows])
    np.testing.assert_array_equal(data.columns(names), expected)
    np.testing.assert_array_equal(data.runs, [float(r["runs"]) for r in rows])
    with pytest.raises(InputError, match="no column 'laser_fov'"):
        data.columns(["laser_fov"])


def _summary(folder: Path, worlds, slam_column=None) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "summary.csv"
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["world", "runs", *ds.COMPONENTS, *(["slam"] if slam_column else [])])
        for i, world in enumerate(worlds):
            writer.writerow([world, 2, 0.1 + i, 0.01, 0.02, 0.001,
                             *([slam_column[i]] if slam_column else [])])
    return path


def _run(folder: Path, world: str, index: int, slam: dict | None) -> None:
    run = folder / world / f"run_{index:03d}"
    run.mkdir(parents=True)
    record = {"world": world, "run_index": index}
    if slam is not None:
        record["slam"] = slam
    (run / "run.json").write_text(json.dumps(record))


def test_the_slam_of_a_summary_comes_from_its_runs_or_its_column(tmp_path):
    path = _summary(tmp_path / "c", ["w0", "w1", "w2"])
    _run(tmp_path / "c", "w0", 0, {"type": "karto", "params_hash": "k"})
    _run(tmp_path / "c", "w0", 1, {"type": "karto", "params_hash": "k"})
    _run(tmp_path / "c", "w1", 0, None)                     # older record: gmapping
    rows = sources.read_error_table(path, "realistic")      # w2 has no runs: gmapping
    assert [r.slam for r in rows] == ["karto", "gmapping", "gmapping"]
    _run(tmp_path / "c", "w1", 1, {"type": "karto"})
    with pytest.raises(InputError, match="building 'w1' has runs of two SLAM algorithms"):
        sources.read_error_table(path, "realistic")
    column = _summary(tmp_path / "d", ["w0", "w1"], ["karto", ""])
    assert [r.slam for r in sources.read_error_table(column, "s")] == ["karto", "gmapping"]
    bad = _summary(tmp_path / "e", ["w0", "w1"], ["karto", "hector"])
    with pytest.raises(InputError, match=r"summary.csv:3: unknown SLAM algorithm 'hector'"):
        sources.read_error_table(bad, "s")


def test_thesis_rows_are_gmapping(shared_data):
    rows = sources.read_error_table(shared_data / "thesis" / "stats_realistic.csv", "realistic")
    assert {r.slam for r in rows} == {"gmapping"}


TINY = """learning:
  models: [single, elasticnet]
  elasticnet: {alphas: [0.01, 0.1, 1.0], l1_ratios: [0.5, 1.0]}
  conformal: {cv: 3}
  evaluation: {n_splits: 3}
"""


def test_learn_train_slam_trains_on_one_algorithm_and_the_card_says_which(tmp_path, capsys):
    data = synthetic_dataset(n=40)
    data.slam = ["karto" if i % 2 else "gmapping" for i in range(len(data))]
    ds.write_dataset(data, tmp_path / "mixed.csv")
    (tmp_path / "learning.yaml").write_text(TINY)
    common = ["--models-dir", str(tmp_path / "models"), "--config",
              str(tmp_path / "learning.yaml")]
    assert main(["learn", "train", str(tmp_path / "mixed.csv"), "--name", "k", "--slam",
                 "slam_toolbox", *common]) == 0
    assert main(["learn", "train", str(tmp_path / "mixed.csv"), "--name", "g", *common]) == 0
    karto = json.loads((tmp_path / "models" / "k" / "card.json").read_text())
    gmapping = json.loads((tmp_path / "models" / "g" / "card.json").read_text())
    assert karto["slam"] == "karto" and gmapping["slam"] == "gmapping"
    assert karto["training_buildings"] == data.worlds[1::2]
    assert gmapping["training_buildings"] == data.worlds[0::2]
    ds.write_dataset(data.select_slam("karto"), tmp_path / "karto.csv")
    capsys.readouterr()
    assert main(["learn", "evaluate", str(tmp_path / "karto.csv"), "--out",
                 str(tmp_path / "ev"), "--config", str(tmp_path / "learning.yaml")]) == 2
    err = capsys.readouterr().err
    assert "no rows of SLAM algorithm 'gmapping'" in err and "--slam" in err
    assert not (tmp_path / "ev").exists()


def test_predict_slam_picks_a_model_of_that_algorithm(tmp_path, capsys):
    """--slam karto: refused while no folder was trained on Karto runs; with one, --model best
    picks it, and a named GMapping folder is refused."""
    import shutil

    world = str(ROOT / "worlds" / "tiny.world")
    models = tmp_path / "models"
    shutil.copytree(ROOT / "models" / "thesis-realistic", models / "thesis-realistic")
    base = ["predict", world, "--models-dir", str(models), "--json"]
    assert main([*base, "--slam", "karto"]) == 2
    assert "no model of karto's error" in capsys.readouterr().err
    card_path = models / "thesis-realistic" / "card.json"
    card = json.loads(card_path.read_text())
    shutil.copytree(models / "thesis-realistic", models / "karto-own")
    (models / "karto-own" / "card.json").write_text(json.dumps({**card, "slam": "karto",
                                                                "name": "karto-own"}))
    assert main([*base, "--slam", "slam_toolbox"]) == 0
    assert json.loads(capsys.readouterr().out)["model_store"] == "karto-own"
    assert main([*base, "--slam", "gmapping"]) == 0
    assert json.loads(capsys.readouterr().out)["model_store"] == "thesis-realistic"
    assert main([*base, "--slam", "karto", "--model", "thesis-realistic"]) == 2
    assert "trained on gmapping runs" in capsys.readouterr().err


def test_learn_dataset_slam_keeps_one_algorithm(tmp_path, capsys):
    """learn dataset --slam NAME writes only that algorithm's rows (an alias names it too) and
    refuses, writing nothing, an algorithm the table does not hold."""
    path = _summary(tmp_path / "c", ["w0", "w1", "w2"], ["karto", "gmapping", "karto"])
    features = tmp_path / "features.csv"
    features.write_text("world,feature_version,area\nw0,v1,10\nw1,v1,20\nw2,v1,30\n")
    common = ["learn", "dataset", "--errors", str(path), "--features", str(features),
              "--thesis-setting", "realistic"]
    assert main([*common, "--slam", "slam_toolbox", "--out", str(tmp_path / "k.csv")]) == 0
    karto = ds.read_dataset(tmp_path / "k.csv")
    assert karto.worlds == ["w0", "w2"] and set(karto.slam) == {"karto"}
    assert main([*common, "--out", str(tmp_path / "all.csv")]) == 0
    assert ds.read_dataset(tmp_path / "all.csv").worlds == ["w0", "w1", "w2"]
    only_karto = _summary(tmp_path / "d", ["w0", "w1", "w2"], ["karto"] * 3)
    capsys.readouterr()
    assert main([*common[:3], str(only_karto), *common[4:], "--slam", "gmapping",
                 "--out", str(tmp_path / "g.csv")]) == 2
    assert "no rows of SLAM algorithm 'gmapping'" in capsys.readouterr().err
    assert not (tmp_path / "g.csv").exists()
