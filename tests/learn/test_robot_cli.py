"""``slam-predict learn robots``: the happy path on a small synthetic campaign and its
bad-input rows (exit 2, one line, nothing written)."""
from __future__ import annotations

import json
import shutil

import pytest

from slam_predict.cli.learn_robots_cmd import DEPRECATED
from slam_predict.cli.main import main
from slam_predict.learn.robot.predict import RobotModel

from . import robot_synthetic as syn

FAST = """robot_learning:
  plan_features: [building_area, voronoi_traversal_distance]
  models: [elasticnet]
  folds: 2
  conformal_folds: 2
  elasticnet: {alphas: [0.001, 0.01, 0.1], l1_ratios: [1.0], cv: 3}
"""


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("robots_cli")
    worlds, robots, records = syn.campaign(folder / "data", n_worlds=8, n_configs=4)
    syn.write_features(folder / "features.csv", worlds)
    syn.write_design(folder / "design.yaml", worlds, robots)
    other = [dict(r, fov=r["fov"] - 1.0) for r in robots]
    syn.write_design(folder / "other_design.yaml", worlds, other)
    (folder / "fast.yaml").write_text(FAST)
    return folder, records


def args(folder, *extra):
    return ["learn", "robots", str(folder / "data"), "--features", str(folder / "features.csv"),
            "--config", str(folder / "fast.yaml"), *extra]


def test_evaluate_and_train(inputs, tmp_path, capsys):
    folder, _ = inputs
    out, models = tmp_path / "ev", tmp_path / "models"
    assert main(args(folder, "--out", str(out), "--name", "own-robots", "--models-dir",
                     str(models), "--seed", "3", "--design", str(folder / "design.yaml"))) == 0
    printed = capsys.readouterr().out
    assert "64 runs, 32 points, 8 buildings, 4 configurations; best: trans_mean elasticnet" \
        in printed
    assert f"model written to {models / 'own-robots'}" in printed
    for name in ("robots_eval.md", "robots_eval.csv", "robots_predictions.csv", "runs.csv",
                 "points.csv", "features.csv", "best.json"):
        assert (out / name).is_file(), name
    page = (out / "robots_eval.md").read_text()
    assert "## Held-out buildings × held-out configurations" in page
    assert "| mean ε_t | elasticnet **(best)** | 32 |" in page
    assert page.count("| ≤ 20 % |") == 3 and "| pass |" in page  # one header per protocol
    assert "- R² ceiling from run-to-run noise (what exact true means would score against " \
        "these measured point means): mean ε_t 0." in page and "(32 points)" in page
    header = (out / "robots_eval.csv").read_text().splitlines()[0]
    assert header.startswith("protocol,component,model,n_points,median_pct_error,r2,coverage")
    from slam_predict.learn.dataset import read_dataset
    from slam_predict.learn.robot.inputs import ALL_ROBOT_INPUTS

    for points in (read_dataset(out / "points.csv"),
                   read_dataset(models / "own-robots" / "training_points.csv")):
        assert len(points) == 32 and sorted(points.robot_inputs) == sorted(ALL_ROBOT_INPUTS)
        assert set(points.setting) == {"robots"} and set(points.slam) == {"gmapping"}
        assert set(points.runs) == {2.0} and len(set(points.robot)) == 4
    card = json.loads((models / "own-robots" / "card.json").read_text())
    assert card["slam"] == "gmapping"
    card = json.loads((models / "own-robots" / "card.json").read_text())
    assert card["robot_learning_config"]["seed"] == 3
    metrics = card["components"]["trans_mean"]["models"]["elasticnet"]["metrics"]
    assert set(metrics) == {"buildings", "configs", "both"} and metrics["both"]["n_points"] == 32
    model = RobotModel.load(models / "own-robots")
    assert model.card["features"] == ["building_area", "voronoi_traversal_distance"]
    assert model.max_urange_m == 30.0 and "maxUrange 30 m" in page
    ranges = model.card["input_ranges"]
    assert ranges["laser_range_max_m"] == [3.5, 30.0] and ranges["laser_fov_deg"] == [180, 360]
    assert model.card["design"]["bounds"]["odom_xy_error"] == pytest.approx([0.0, 0.02])
    assert card["sources"]["design"] == str(folder / "design.yaml")
    assert model.derived == ["laser_blind_fraction"] and "laser_blind_fraction" in page
    assert card["exploration"]["min_coverage"] == 0.5
    assert [e["runs"] for e in card["exploration"]["by_config"].values()] == [16] * 4
    assert "failed explorations" not in page          # every synthetic run explored 0.99


def test_failed_explorations_are_listed(inputs, tmp_path):
    folder, records = inputs
    record = dict(records[0])
    path = record.pop("path")
    try:
        with open(path, "w") as handle:
            json.dump(dict(record, coverage=0.2), handle)
        assert main(args(folder, "--out", str(tmp_path / "ev"))) == 0
    finally:
        with open(path, "w") as handle:
            json.dump(record, handle)
    page = (tmp_path / "ev" / "robots_eval.md").read_text()
    config = record["design"]["config"]
    assert f"- failed explorations (coverage < 0.5, not learned from): 1 of 64 runs; {config} (" \
        in page and ") 1/16" in page


def test_features_of_the_evaluation_folder_are_reusable(inputs, tmp_path):
    folder, _ = inputs
    assert main(args(folder, "--out", str(tmp_path / "a"))) == 0
    again = ["learn", "robots", str(folder / "data"), "--features",
             str(tmp_path / "a" / "features.csv"), "--config", str(folder / "fast.yaml"),
             "--out", str(tmp_path / "b")]
    assert main(again) == 0
    assert json.loads((tmp_path / "a" / "features.json").read_text())["feature_config"] == {}
    assert (tmp_path / "a" / "robots_eval.csv").read_text() == \
        (tmp_path / "b" / "robots_eval.csv").read_text()


def run_error(argv, capsys) -> str:
    code = main(argv)
    lines = [line for line in capsys.readouterr().err.strip().splitlines()
             if line != DEPRECATED]
    assert code == 2 and len(lines) == 1, lines
    return lines[0]


def test_evaluate_and_train_verbs_with_runs_match_the_old_spelling(inputs, tmp_path, capsys):
    folder, _ = inputs
    common = ["--features", str(folder / "features.csv"), "--config", str(folder / "fast.yaml"),
              "--seed", "3", "--design", str(folder / "design.yaml")]
    old_out, old_models = tmp_path / "old_ev", tmp_path / "old_models"
    assert main(["learn", "robots", str(folder / "data"), *common, "--out", str(old_out),
                 "--name", "own-robots", "--models-dir", str(old_models)]) == 0
    assert capsys.readouterr().err.strip() == DEPRECATED
    new_out, new_models = tmp_path / "new_ev", tmp_path / "new_models"
    assert main(["learn", "evaluate", "--runs", str(folder / "data"), *common,
                 "--out", str(new_out)]) == 0
    assert main(["learn", "train", "--runs", str(folder / "data"), *common, "--name",
                 "own-robots", "--models-dir", str(new_models),
                 "--evaluation-out", str(tmp_path / "train_ev")]) == 0
    assert "deprecated" not in capsys.readouterr().err
    for name in ("robots_eval.md", "robots_eval.csv", "best.json", "points.csv"):
        old_text = (old_out / name).read_text()
        assert (new_out / name).read_text() == old_text == (tmp_path / "train_ev" / name
                                                            ).read_text(), name
    old_card = json.loads((old_models / "own-robots" / "card.json").read_text())
    new_card = json.loads((new_models / "own-robots" / "card.json").read_text())
    assert new_card == old_card


@pytest.mark.parametrize("argv, message", [
    (["learn", "evaluate", "--out", "{tmp}/ev"], "give a DATASET (from 'learn dataset') or "
                                                 "--runs DATA_DIR..."),
    (["learn", "evaluate", "d.csv", "--runs", "x", "--out", "{tmp}/ev"],
     "give either DATASET or --runs DATA_DIR..., not both"),
    (["learn", "evaluate", "d.csv", "--folds", "3", "--out", "{tmp}/ev"],
     "--folds applies to robot-aware models (--runs) only"),
    (["learn", "train", "--runs", "x", "--features", "f.csv", "--splits", "3", "--name", "n"],
     "--splits applies to plan-only models (DATASET) only"),
    (["learn", "evaluate", "--runs", "x", "--out", "{tmp}/ev"],
     "with --runs give one of --worlds DIR or --features CSV"),
])
def test_evaluate_and_train_refuse_a_mix_of_families(argv, message, tmp_path, capsys):
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    assert message in run_error(argv, capsys)
    assert not (tmp_path / "ev").exists()


@pytest.mark.parametrize("extra, message", [
    ((), "nothing to write: give --out EVAL_DIR and/or --name NAME"),
    (("--out", "{tmp}/ev", "--folds", "1"), "--folds must be ≥ 2, got 1"),
    (("--out", "{tmp}/ev", "--repeats", "0"), "--repeats must be ≥ 1, got 0"),
    (("--out", "{tmp}/ev", "--estimators", "svm"), "unknown model kind 'svm'"),
    (("--out", "{tmp}/ev", "--jobs", "0"), "--jobs must be ≥ 1, got 0"),
    (("--out", "{tmp}/full"), "--out folder exists and is not empty"),
    (("--name", "a/b"), "--name must be a folder name"),
])
def test_bad_options(inputs, tmp_path, capsys, extra, message):
    folder, _ = inputs
    (tmp_path / "full").mkdir()
    (tmp_path / "full" / "x").write_text("x")
    extra = [e.replace("{tmp}", str(tmp_path)) for e in extra]
    assert message in run_error(args(folder, *extra), capsys)
    assert not (tmp_path / "ev").exists()


def test_bad_inputs(inputs, tmp_path, capsys):
    folder, records = inputs
    out = ["--out", str(tmp_path / "ev")]
    err = run_error(["learn", "robots", str(tmp_path / "nope"), "--features",
                     str(folder / "features.csv"), *out], capsys)
    assert "nope: campaign folder not found" in err
    err = run_error(["learn", "robots", str(folder / "data"), "--features",
                     str(tmp_path / "f.csv"), *out], capsys)
    assert "f.csv: table not found" in err
    broken = tmp_path / "broken"
    (broken / "w00" / "run_000").mkdir(parents=True)
    (broken / "w00" / "run_000" / "run.json").write_text("[1, 2")
    err = run_error(["learn", "robots", str(broken), "--features",
                     str(folder / "features.csv"), *out], capsys)
    assert "run.json: unreadable run record (JSONDecodeError)" in err
    (tmp_path / "bad.yaml").write_text("robot_learning:\n  modles: [elasticnet]\n")
    err = run_error(["learn", "robots", str(folder / "data"), "--features",
                     str(folder / "features.csv"), "--config", str(tmp_path / "bad.yaml"),
                     *out], capsys)
    assert "unknown config key 'modles'" in err and "did you mean 'models'" in err
    (tmp_path / "feat.yaml").write_text("robot_learning:\n  plan_features: [area]\n")
    err = run_error(["learn", "robots", str(folder / "data"), "--features",
                     str(folder / "features.csv"), "--config", str(tmp_path / "feat.yaml"),
                     *out], capsys)
    assert "plan feature 'area' is not in the feature table" in err
    err = run_error(args(folder, *out, "--design", str(folder / "other_design.yaml")), capsys)
    assert "other_design.yaml: configuration 'c00': laser_fov_deg is" in err
    err = run_error(args(folder, *out, "--design", str(tmp_path / "none.yaml")), capsys)
    assert "none.yaml" in err and "not found" in err
    (tmp_path / "urange.yaml").write_text("robot_learning:\n  max_urange_m: -1\n")
    err = run_error(args(folder, *out, "--config", str(tmp_path / "urange.yaml")), capsys)
    assert "max_urange_m" in err
    assert not (tmp_path / "ev").exists()


def test_shipped_configuration_is_the_documented_defaults(root):
    from slam_predict.learn.robot.config import RobotLearningConfig, load_robot_learning_config

    assert load_robot_learning_config(root / "config" / "robot_learning.yaml") == \
        RobotLearningConfig()


def test_the_failure_model_sees_a_building_whose_runs_all_failed(inputs, tmp_path):
    """A building without one usable run (every run below min_coverage) is not learnt from by
    the error models, but its runs are failures the failure model must count."""
    folder, records = inputs
    data = tmp_path / "data"
    shutil.copytree(folder / "data", data)
    failing = records[0]["world"]
    for path in data.glob(f"{failing}/run_*/run.json"):
        path.write_text(json.dumps(dict(json.loads(path.read_text()), coverage=0.2)))
    assert main(["learn", "train", "--runs", str(data), "--features",
                 str(folder / "features.csv"), "--config", str(folder / "fast.yaml"),
                 "--name", "m", "--models-dir", str(tmp_path / "models")]) == 0
    card = json.loads((tmp_path / "models" / "m" / "card.json").read_text())
    assert failing not in card["training_buildings"] and len(card["training_buildings"]) == 7
    assert (card["failure"]["runs"], card["failure"]["failed"]) == (64, 8)


def test_runs_collected_without_the_design_join_inside_its_bounds(inputs, tmp_path, capsys):
    """--design with a second campaign collected with one robot file (as the fidelity
    campaign's seed robot): its configuration joins when it lies inside the design's bounds,
    and the card lists it; outside them it is refused naming the input."""
    import numpy as np

    folder, _ = inputs
    worlds = {w: f for w, f in syn.buildings(8, np.random.default_rng(0)).items()
              if w in ("w00", "w01")}
    seed_robot = {"range_max": 30.0, "fov": 270.0, "xy": 0.01, "yaw": syn.YAW}
    extra = tmp_path / "seed_robot"
    syn.write_campaign(extra, worlds, [seed_robot], 2, np.random.default_rng(1), design=False)
    models = tmp_path / "models"
    assert main(["learn", "train", "--runs", str(folder / "data"), str(extra), "--features",
                 str(folder / "features.csv"), "--config", str(folder / "fast.yaml"),
                 "--design", str(folder / "design.yaml"), "--name", "mixed", "--models-dir",
                 str(models)]) == 0
    assert "68 runs, 34 points, 8 buildings, 5 configurations" in capsys.readouterr().out
    configs = json.loads((models / "mixed" / "card.json").read_text())["design"]["configs"]
    assert len(configs) == 5 and sum(not c.startswith("c0") for c in configs) == 1
    narrow = tmp_path / "narrow"
    syn.write_campaign(narrow, worlds, [dict(seed_robot, fov=120.0)], 1,
                       np.random.default_rng(2), design=False)
    err = run_error(["learn", "evaluate", "--runs", str(folder / "data"), str(narrow),
                     "--features", str(folder / "features.csv"), "--config",
                     str(folder / "fast.yaml"), "--design", str(folder / "design.yaml"),
                     "--out", str(tmp_path / "ev")], capsys)
    assert "(runs collected without the design): laser_fov_deg 120 lies outside the " \
           "design's bounds [180, 360]" in err
    assert not (tmp_path / "ev").exists()
