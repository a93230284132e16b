"""``slam-predict learn dataset|evaluate|train`` end to end on small inputs, and bad inputs."""
from __future__ import annotations

import csv
import json

import pytest

from slam_predict.cli.main import main
from slam_predict.learn.dataset import read_dataset

from .conftest import synthetic_dataset

TINY = """learning:
  models: [single, elasticnet]
  elasticnet: {alphas: [0.01, 0.1, 1.0], l1_ratios: [0.5, 1.0]}
  conformal: {cv: 3}
  evaluation: {n_splits: 3}
"""


@pytest.fixture()
def inputs(tmp_path):
    data = synthetic_dataset()
    errors = tmp_path / "summary.csv"
    features = tmp_path / "features.csv"
    with open(errors, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["world", "runs", "trans_mean", "trans_std", "rot_mean", "rot_std"])
        for i, world in enumerate(data.worlds):
            writer.writerow([world, 5, *data.Y[i]])
    with open(features, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["world", *data.feature_names])
        for i, world in enumerate(data.worlds):
            writer.writerow([world, *data.X[i]])
    (tmp_path / "learning.yaml").write_text(TINY)
    return tmp_path


def test_dataset_evaluate_train(inputs, capsys):
    out = inputs / "ds.csv"
    assert main(["learn", "dataset", "--errors", str(inputs / "summary.csv"), "--features",
                 str(inputs / "features.csv"), "--feature-version", "fv1", "--thesis-setting",
                 "realistic", "--slam-config-hash", "h1", "--out", str(out)]) == 0
    data = read_dataset(out)
    assert len(data) == 30 and set(data.slam_config_hash) == {"h1"}
    cfg = str(inputs / "learning.yaml")
    assert main(["learn", "evaluate", str(out), "--out", str(inputs / "ev"), "--config", cfg,
                 "--no-loo"]) == 0
    for name in ("splits.csv", "summary.csv", "tables.md", "regression.png", "best.json"):
        assert (inputs / "ev" / name).is_file()
    assert "Best single feature (like Table 7.1)" in (inputs / "ev" / "tables.md").read_text()
    assert main(["learn", "train", str(out), "--name", "cli-model", "--models-dir",
                 str(inputs / "models"), "--config", cfg]) == 0
    card = json.loads((inputs / "models" / "cli-model" / "card.json").read_text())
    assert card["feature_version"] == "fv1" and card["sources"]["dataset"] == "ds.csv"
    assert "model written to" in capsys.readouterr().out


def test_dataset_min_runs_skips_buildings_with_fewer_runs(inputs):
    """--min-runs keeps the buildings with that many runs and no other (summary.csv 'runs')."""
    rows = list(csv.reader(open(inputs / "summary.csv", newline="")))
    for row in rows[1:4]:
        row[1] = "2"
    with open(inputs / "summary.csv", "w", newline="") as handle:
        csv.writer(handle).writerows(rows)
    args = ["learn", "dataset", "--errors", str(inputs / "summary.csv"), "--features",
            str(inputs / "features.csv"), "--feature-version", "fv1", "--thesis-setting",
            "realistic"]
    assert main([*args, "--min-runs", "3", "--out", str(inputs / "three.csv")]) == 0
    assert main([*args, "--out", str(inputs / "all.csv")]) == 0
    three, every = read_dataset(inputs / "three.csv"), read_dataset(inputs / "all.csv")
    assert set(every.worlds) - set(three.worlds) == {row[0] for row in rows[1:4]}
    assert len(three) == len(every) - 3


def test_dataset_min_runs_errors(inputs, capsys):
    args = ["learn", "dataset", "--errors", str(inputs / "summary.csv"), "--features",
            str(inputs / "features.csv"), "--feature-version", "fv1", "--thesis-setting",
            "realistic", "--out", str(inputs / "x.csv")]
    assert "no building has 6 or more runs" in run_error([*args, "--min-runs", "6"], capsys)
    assert "--min-runs" in run_error([*args, "--min-runs", "0"], capsys)
    assert not (inputs / "x.csv").exists()


def run_error(argv, capsys):
    code = main(argv)
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1, err
    return err


def test_bad_inputs_are_one_line_errors(inputs, capsys):
    err = run_error(["learn", "dataset", "--errors", str(inputs / "nope.csv"), "--features",
                     str(inputs / "features.csv"), "--out", str(inputs / "x.csv")], capsys)
    assert "nope.csv: table not found" in err
    err = run_error(["learn", "dataset", "--errors", str(inputs / "summary.csv"), "--features",
                     str(inputs / "features.csv"), "--out", str(inputs / "x.csv")], capsys)
    assert "give --thesis-setting" in err
    assert not (inputs / "x.csv").exists()
    (inputs / "bad.yaml").write_text("learning:\n  modles: [single]\n")
    err = run_error(["learn", "evaluate", str(inputs / "summary.csv"), "--out",
                     str(inputs / "ev"), "--config", str(inputs / "bad.yaml")], capsys)
    assert "unknown config key 'modles'" in err and "did you mean 'models'" in err
    (inputs / "top.yaml").write_text("learning:\n  models: [single]\nlearnign: {}\n")
    err = run_error(["learn", "evaluate", str(inputs / "summary.csv"), "--out",
                     str(inputs / "ev"), "--config", str(inputs / "top.yaml")], capsys)
    assert "unknown config key 'learnign'" in err and "did you mean 'learning'" in err
    (inputs / "ftop.yaml").write_text("features:\n  mode: documented\nfeatures2: {}\n")
    err = run_error(["learn", "dataset", "--errors", str(inputs / "summary.csv"),
                     "--thesis-setting", "realistic", "--worlds", str(inputs), "--feature-config",
                     str(inputs / "ftop.yaml"), "--out", str(inputs / "x.csv")], capsys)
    assert "ftop.yaml: unknown config key 'features2'" in err
    assert not (inputs / "ev").exists() and not (inputs / "x.csv").exists()


def test_reference_features_cannot_be_shipped(shared_data, tmp_path, capsys):
    table = shared_data / "thesis" / "stats_realistic.csv"
    features = tmp_path / "f.csv"
    with open(table, newline="") as handle:
        rows = list(csv.reader(handle))
    with open(features, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["world", "feature_version", "x"])
        writer.writerows([[r[0], "reference-table", r[1]] for r in rows[1:]])
    out = tmp_path / "ds.csv"
    assert main(["learn", "dataset", "--errors", str(table), "--features", str(features),
                 "--thesis-setting", "realistic", "--out", str(out)]) == 0
    err = run_error(["learn", "train", str(out), "--name", "x", "--models-dir",
                     str(tmp_path / "m")], capsys)
    assert "cannot be shipped" in err
