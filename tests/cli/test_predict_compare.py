"""``slam-predict predict PLAN --compare A B`` and ``--slam A`` with models trained for each
algorithm (tests/cli/compare_models.py: real campaigns, the second relabelled as Karto): the
side-by-side output, the call and its probability against a direct computation, "too close to
call", the robot-aware path, ``rosrun slam_predict predict`` and the one-line refusals."""
from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from compare_models import copy_as, relabel, train

from slam_predict.cli.main import main

LARGE = "worlds/office_1500.world"     # Karto's model expects the lower error there
SMALL = "worlds/office_500.world"      # the two models disagree by less than a call needs
ROBOT = "config/robots/urg_240_5p6.yaml"


@pytest.fixture(scope="module")
def models(tmp_path_factory) -> Path:
    """tiny-gmapping (fidelity_seed_study) and tiny-karto (fidelity_sizes, card slam: karto,
    the higher priority: chosen for GMapping too if the card's algorithm were ignored)."""
    folder = tmp_path_factory.mktemp("compare_models")
    with pytest.warns(RuntimeWarning):    # empty error columns of the one-run campaign
        train(folder, "tiny-gmapping", "fidelity_seed_study")
        relabel(train(folder, "tiny-karto", "fidelity_sizes", slam="karto"), priority=5)
    return folder


@pytest.fixture(autouse=True)
def at_root(root, monkeypatch):
    """Run from the repository's top (the plans and robot files by relative path)."""
    monkeypatch.chdir(root)


@pytest.fixture
def call(capsys):
    """call(*argv) → (exit code, stdout, stderr) of ``slam-predict predict *argv``."""
    def run(*argv) -> tuple[int, str, str]:
        code = main(["predict", *map(str, argv)])
        captured = capsys.readouterr()
        return code, captured.out, captured.err
    return run


def compare_json(call, models, world) -> dict:
    code, out, err = call(world, "--compare", "gmapping", "karto", "--models-dir",
                          str(models), "--json")
    assert code == 0, err
    return json.loads(out)


def direct(root, models, world: str, n: int = 1_000_000) -> tuple[dict, float]:
    """({model: its trans_mean entry}, P(Karto's ε_t < GMapping's)), the slow way: each model
    loaded and evaluated on the plan's features, then a million draws of each prediction's
    distribution (the median, a fair coin for the side, a half-normal whose scale puts the
    interval's end at the 95th percentile of that side's normal)."""
    from slam_predict.features.plan import plan_features
    from slam_predict.learn.model import load_model
    from slam_predict.world.load import load_plan

    z95 = 1.6448536269514722   # Φ⁻¹(0.95)
    rng = np.random.default_rng(5)
    plan = load_plan(str(root / world))
    entries, draws = {}, {}
    for name in ("tiny-gmapping", "tiny-karto"):
        model = load_model(models / name)
        entry = model.predict(plan_features(plan, model.feature_config))["trans_mean"]
        half = np.abs(rng.standard_normal(n))
        upper = rng.random(n) < 0.5
        draws[name] = np.where(upper, entry["value"] + (entry["high"] - entry["value"]) / z95
                               * half, entry["value"] - (entry["value"] - entry["low"]) / z95
                               * half)
        entries[name] = entry
    return entries, float(np.mean(draws["tiny-karto"] < draws["tiny-gmapping"]))


def test_compare_side_by_side_and_the_call(root, models, call):
    result = compare_json(call, models, LARGE)
    assert result["compare"] == ["gmapping", "karto"] and result["world"] == "office_1500"
    gmapping, karto = (result["predictions"][s] for s in ("gmapping", "karto"))
    assert gmapping["model_store"] == "tiny-gmapping" and karto["model_store"] == "tiny-karto"
    entries, p_karto = direct(root, models, LARGE)
    for name, prediction in (("tiny-gmapping", gmapping), ("tiny-karto", karto)):
        for key in ("value", "low", "high"):
            assert prediction["trans_mean"][key] == pytest.approx(entries[name][key])
    decision = result["decision"]
    assert decision["component"] == "trans_mean" and decision["threshold"] == 0.75
    assert decision["probability"]["karto"] == pytest.approx(p_karto, abs=0.003)
    assert p_karto > 0.75 and decision["verdict"] == "karto"
    code, out, err = call(LARGE, "--compare", "gmapping", "slam_toolbox",
                          "--models-dir", str(models))
    assert code == 0, err
    lines = out.splitlines()
    assert lines[0] == "office_1500: predicted localization error of GMapping and Karto " \
                       "(90 % intervals)"
    assert "gmapping: tiny-gmapping (plan-only" in lines[2] and "karto: tiny-karto" in lines[2]
    row = next(line for line in lines if line.strip().startswith("trans_mean"))
    for prediction in (gmapping, karto):
        entry = prediction["trans_mean"]
        assert f"{entry['value']:.3f} m ({entry['low']:.3f}–{entry['high']:.3f})" in row
    assert row.index(f"{gmapping['trans_mean']['value']:.3f}") < \
        row.index(f"{karto['trans_mean']['value']:.3f}")
    call_line = lines.index(next(line for line in lines if line.startswith("expected")))
    assert lines[call_line].startswith("expected to be more accurate here: Karto")
    assert f"probability {decision['probability']['karto']:.2f} that karto's is the lower" in \
        lines[call_line + 1]


def test_too_close_to_call(root, models, tmp_path, call):
    result = compare_json(call, models, SMALL)
    decision = result["decision"]
    assert decision["verdict"] == "too_close_to_call"
    assert 0.5 < decision["probability"]["karto"] < 0.75
    _, p_karto = direct(root, models, SMALL)
    assert decision["probability"]["karto"] == pytest.approx(p_karto, abs=0.003)
    same = tmp_path / "models"                 # the GMapping model also labelled Karto
    shutil.copytree(models / "tiny-gmapping", same / "tiny-gmapping")
    copy_as(models / "tiny-gmapping", same / "as-karto", "karto")
    code, out, err = call(SMALL, "--compare", "karto", "gmapping", "--models-dir",
                          str(same), "--component", "trans_mean")
    assert code == 0, err
    lines = out.splitlines()
    assert [line.split()[0] for line in lines[3:5]] == ["karto", "trans_mean"]
    assert not any(line.strip().startswith("rot_mean") for line in lines)
    assert lines[5].startswith("too close to call: mean translational error")
    assert "probability 0.50 that karto's is the lower, 0.50 gmapping's" in lines[6]


def test_slam_picks_the_model_trained_for_it(models, call):
    for slam, name, label in (("karto", "tiny-karto", "Karto"),
                              ("gmapping", "tiny-gmapping", "GMapping")):
        code, out, err = call(SMALL, "--slam", slam, "--models-dir", str(models),
                              "--component", "trans_mean", "--json")
        assert code == 0, err
        result = json.loads(out)
        assert result["model_store"] == name and result["slam"] == slam
        code, out, err = call(SMALL, "--slam", slam, "--models-dir", str(models),
                              "--component", "trans_mean")
        assert out.startswith(f"office_500: predicted {label} localization error"), err


def test_robot_aware_compare(robot_models_dir, tmp_path, call):
    """The robot-aware GMapping model and a copy labelled Karto: the same prediction, so
    exactly even; the robot enters both."""
    folder = tmp_path / "models"
    shutil.copytree(robot_models_dir / "own-robots", folder / "own-robots")
    copy_as(robot_models_dir / "own-robots", folder / "karto-robots", "karto")
    code, out, err = call(SMALL, "--compare", "gmapping", "karto", "--robot", ROBOT,
                          "--models-dir", str(folder), "--json")
    assert code == 0, err
    result = json.loads(out)
    for slam, name in (("gmapping", "own-robots"), ("karto", "karto-robots")):
        prediction = result["predictions"][slam]
        assert prediction["model_store"] == name and prediction["model_takes_robot"] is True
        assert prediction["robot"]["name"] == "urg_240_5p6"
    assert result["decision"]["probability"]["karto"] == pytest.approx(0.5, abs=1e-12)
    assert result["decision"]["verdict"] == "too_close_to_call"


def test_rosrun_predict_passes_compare_through(root, models):
    proc = subprocess.run([sys.executable, str(root / "scripts" / "predict"), SMALL,
                           "--compare", "gmapping", "karto", "--models-dir", str(models),
                           "--json", "__name:=predict"], cwd=root, capture_output=True,
                          text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout)["decision"]["verdict"] == "too_close_to_call"


def one_line_error(call, *argv) -> str:
    code, out, err = call(*argv)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and not out and "Traceback" not in err, err
    return lines[0]


REFUSALS = [
    (["--slam", "karto"], "only-gmapping",
     ["--slam karto: no model of karto's error", "slam-predict collect WORLDS --slam karto",
      "config/collect_karto.yaml", "learn train DATASET --slam karto",
      "docs/howto/choose-slam.md"]),
    (["--compare", "gmapping", "karto"], "only-gmapping",
     ["--compare gmapping karto: no model of karto's error"]),
    (["--compare", "gmapping", "karto", "--robot", ROBOT], "robots",
     ["--compare gmapping karto: no robot-aware model of karto's error",
      "learn train --runs DATA --design DESIGN --slam karto"]),
    (["--compare", "gmapping", "karot"], "both",
     ["--compare karot: unknown SLAM back-end", "did you mean 'karto'"]),
    (["--compare", "karto", "slam_toolbox"], "both", ["name two different SLAM algorithms"]),
    (["--compare", "gmapping", "karto", "--model", "tiny-karto"], "both", ["give no --model"]),
    (["--compare", "gmapping", "karto", "--slam", "karto"], "both",
     ["either --slam or --compare"]),
    (["--compare", "gmapping", "karto", "--simulate", "1", "--out", "x"], "both",
     ["--compare only predicts"]),
    (["--slam", "karto", "--simulate", "1", "--out", "x", "--settings", "config/collect.yaml"],
     "both", ["config/collect.yaml", "slam.type is gmapping, not karto"]),
    (["--slam", "karto", "--model", "tiny-gmapping"], "both",
     ["--slam karto:", "tiny-gmapping was trained on gmapping runs, not karto"]),
]


@pytest.mark.parametrize("argv, folder, words", REFUSALS,
                         ids=[" ".join(a) for a, _, _ in REFUSALS])
def test_refusals_are_one_line_exit_2(models, tmp_path, call, request, argv, folder, words):
    """``folder``: both test models, only the GMapping one, or only the robot-aware
    own-robots (GMapping)."""
    if folder == "only-gmapping":
        shutil.copytree(models / "tiny-gmapping", tmp_path / "tiny-gmapping")
    where = {"both": models, "only-gmapping": tmp_path,
             "robots": request.getfixturevalue("robot_models_dir")}[folder]
    err = one_line_error(call, SMALL, *argv, "--models-dir", str(where))
    assert all(word in err for word in words), err


def test_features_are_computed_once_per_feature_version():
    """Two models of one feature version (and sight-line configuration) share the plan's
    features; another version or a sight-line reader gets its own computation."""
    from types import SimpleNamespace

    from slam_predict.cli.predict_compare import predictions

    def model(version, sightline=None):
        return SimpleNamespace(card={"feature_version": version}, sightline_config=sightline)

    def check(models, fresh):
        given = []

        def predict(world, model, features=None):
            given.append(features)
            return {"features": {"for": id(model)}}
        predictions("plan", models, predict)
        assert [features is None for features in given] == fresh

    check({"gmapping": model("2+a"), "karto": model("2+a")}, [True, False])
    check({"gmapping": model("2+a"), "karto": model("2+b")}, [True, True])
    check({"gmapping": model("2+a"), "karto": model("2+a", {"rays": 8})}, [True, True])


def test_simulate_takes_the_algorithms_settings():
    """``--slam karto --simulate`` simulates with Karto's shipped settings, as collect does."""
    import argparse

    from slam_predict.cli.predict_simulate import SIM_OPTIONS, check_options

    def options(slam):
        return argparse.Namespace(**{**dict.fromkeys(SIM_OPTIONS), "out": "sim"},
                                  simulate="1", slam=slam)

    args = options("slam_toolbox")
    check_options(args)
    assert Path(args.settings).name == "collect_karto.yaml"
    args = options(None)
    check_options(args)
    assert args.settings is None     # collect's default, config/collect.yaml


def test_robot_aware_compare_names_each_algorithms_range_cap(robot_models_dir, tmp_path, call):
    """With an 80 m laser each algorithm uses its own range cap, and the robot line says so."""
    folder = tmp_path / "models"
    shutil.copytree(robot_models_dir / "own-robots", folder / "own-robots")
    copy_as(robot_models_dir / "own-robots", folder / "karto-robots", "karto")
    code, out, err = call(SMALL, "--compare", "gmapping", "karto", "--robot",
                          "config/robots/seed_realistic.yaml", "--models-dir", str(folder))
    assert code == 0, err
    line = next(x for x in out.splitlines() if x.startswith("robot seed_realistic"))
    assert "robot inputs: GMapping: laser range 30 m used (laser 80 m, GMapping's maxUrange " \
           "30 m)" in line
    assert "; Karto: laser range 30 m used (laser 80 m, Karto's max_laser_range 30 m)" in line
