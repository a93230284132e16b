"""`slam-predict predict PLAN --simulate N --out DIR`: a real short simulation of the tiny world
(figures recomputed from the run.json files, resume, refusal of other arguments) and one-line
errors for bad inputs, with nothing written."""
import contextlib
import io
import json
from pathlib import Path

import cv2
import numpy as np
import pytest
from robot_runs import LDS, TINY, short_settings
from scipy import stats

from slam_predict.cli.main import main


def call(argv):
    """(exit code, stdout, stderr) of ``slam-predict predict ...``."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["predict", *argv])
    return code, out.getvalue(), err.getvalue()


def run_jsons(out: Path) -> dict[Path, bytes]:
    return {p: p.read_bytes() for p in sorted(out.glob("tiny/run_*/run.json"))}


@pytest.fixture(scope="module")
def simulated(tmp_path_factory, root):
    """Two short runs of the tiny world with the LDS robot: (argv, folder, JSON result). The
    models folder holds only the shipped plan-only thesis-realistic: no robot-aware model."""
    import shutil

    folder = tmp_path_factory.mktemp("simulate")
    shutil.copytree(root / "models" / "thesis-realistic", folder / "models" / "thesis-realistic")
    argv = [str(TINY), "--simulate", "2", "--out", str(folder / "out"), "--settings",
            str(short_settings(folder)), "--robot", str(LDS), "--no-progress", "--json",
            "--models-dir", str(folder / "models")]
    code, out, err = call(argv)
    assert code == 0, err
    return argv, folder / "out", json.loads(out)


def test_figures_are_the_statistics_of_the_run_records(simulated):
    _, out, result = simulated
    sim = result["simulation"]
    assert sim["runs"] == 2 and sim["runs_new"] == 2 and sim["run_indices"] == [0, 1]
    assert result["model_takes_robot"] is False and sim["robot"] == str(LDS)
    records = [json.loads(b) for b in run_jsons(out).values()]
    assert len(records) == 2
    assert all(r["sensor"]["laser"]["range_max"] == 3.5 for r in records)
    for comp, key in [("trans", "trans_mean"), ("rot", "rot_mean")]:
        x = np.array([r["metric"][key] for r in records])
        mean, std = sim["measured"][f"{comp}_mean"], sim["measured"][f"{comp}_std"]
        ref = stats.t.interval(0.95, 1, loc=x.mean(), scale=stats.sem(x))
        assert mean["value"] == pytest.approx(x.mean(), rel=1e-12)
        assert mean["low"] == pytest.approx(max(ref[0], 0.0), abs=1e-12)
        assert mean["high"] == pytest.approx(ref[1], rel=1e-12)
        assert std["value"] == pytest.approx(np.std(x), rel=1e-12)
        ss = np.sum((x - x.mean()) ** 2)
        assert std["low"] == pytest.approx(np.sqrt(ss / stats.chi2.ppf(0.975, 1)), rel=1e-9)
        assert std["high"] == pytest.approx(np.sqrt(ss / stats.chi2.ppf(0.025, 1)), rel=1e-9)
        assert mean["method"] == "t" and std["method"] == "chi-square"
    assert result["model_store"] == "thesis-realistic" and "trans_mean" in result
    assert (out / "tiny.world").is_file() and (out / "tiny.png").is_file()
    assert (out / "summary.csv").is_file()
    campaign = json.loads((out / "campaign.json").read_text())
    assert campaign["plan"]["name"] == "tiny" and campaign["base_seed"] == 0


def test_resume_runs_nothing_and_prints_the_same_figures(simulated):
    argv, out, result = simulated
    before = run_jsons(out)
    code, text, err = call([a for a in argv if a != "--json"])
    assert code == 0, err
    assert run_jsons(out) == before
    assert "measured over 2 simulated runs (0 new" in text
    assert "model: thesis-realistic (does not take the robot into account)" in text
    value = result["simulation"]["measured"]["trans_mean"]["value"]
    assert f"measured   {value:.3f} m" in text


def test_a_robot_aware_model_predicts_beside_the_measured_values(simulated, robot_models_dir):
    """With a robot-aware model installed the prediction takes the robot (resume: no run)."""
    argv, out, _ = simulated
    before = run_jsons(out)
    code, text, err = call([*argv, "--models-dir", str(robot_models_dir)])
    assert code == 0, err
    result = json.loads(text)
    assert result["model_takes_robot"] is True and result["model_store"] == "own-robots"
    assert result["robot"]["name"] == "lds_360_3p5" and result["simulation"]["runs_new"] == 0
    assert result["trans_mean"]["model"].startswith("own-robots/")
    code, text, err = call([a for a in argv if a != "--json"]
                           + ["--models-dir", str(robot_models_dir)])
    assert code == 0, err
    assert ("model: own-robots (robot-aware: takes the robot into account; laser range 3.5 m, "
            "fov 360°") in text
    assert run_jsons(out) == before


@pytest.mark.parametrize("change", [
    ["--seed", "1"],
    ["--robot", None],
    ["--start", "-3.5", "-2.5"],
], ids=["seed", "no robot", "other plan"])
def test_other_arguments_are_refused(simulated, change):
    argv, out, _ = simulated
    argv = list(argv)
    if change[1] is None:
        i = argv.index(change[0])
        del argv[i:i + 2]
    else:
        argv += change
    files = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}
    code, _, err = call(argv)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and "campaign.json" in lines[0], err
    assert {p: p.read_bytes() for p in out.rglob("*") if p.is_file()} == files
    assert ("--force" in lines[0]) == (change[0] != "--start"), err   # a plan is never forced


def copy_of(simulated, tmp_path):
    """The simulated campaign copied (the module's own folder stays as it is)."""
    import shutil

    argv, out, _ = simulated
    copy = tmp_path / "out"
    shutil.copytree(out, copy)
    argv = list(argv)
    argv[argv.index(str(out))] = str(copy)
    return argv, copy


def test_force_continues_with_another_seed_but_never_another_plan(simulated, tmp_path):
    argv, out = copy_of(simulated, tmp_path)
    before = run_jsons(out)
    code, _, err = call([*argv, "--start", "-3.5", "-2.5", "--force"])
    assert code == 2 and "simulated another version of plan" in err, err
    code, stdout, err = call([*argv, "--seed", "1", "--force"])
    assert code == 0, err
    assert json.loads(stdout)["simulation"]["runs_new"] == 0 and run_jsons(out) == before
    campaign = json.loads((out / "campaign.json").read_text())
    assert campaign["base_seed"] == 1 and campaign["history"][0]["base_seed"] == 0


def test_one_run_has_no_measured_spread(simulated, tmp_path):
    argv, _ = copy_of(simulated, tmp_path)
    argv[argv.index("2")] = "1"
    argv.remove("--json")
    code, stdout, err = call(argv)
    assert code == 0, err
    assert "measured over 1 simulated run (" in stdout
    assert stdout.count("measured   n/a (1 run)") == 2     # trans_std and rot_std
    code, stdout, _ = call([*argv, "--json"])
    measured = json.loads(stdout)["simulation"]["measured"]
    assert measured["trans_std"]["status"] == "n/a" and measured["trans_std"]["value"] is None
    assert measured["trans_mean"]["status"] == "ok"


def open_plan(tmp_path: Path) -> Path:
    """An image whose free space all touches the border: no enclosed building."""
    path = tmp_path / "open.png"
    image = np.full((60, 60), 255, np.uint8)
    image[20:40, 20:40] = 0
    cv2.imwrite(str(path), image)
    return path


def bad_robot(tmp_path: Path) -> Path:
    path = tmp_path / "bad_robot.yaml"
    path.write_text(LDS.read_text().replace("  fov: 360.0", "  fvo: 360.0"))
    return path


BAD_INPUTS = [
    ("--simulate 0", lambda t: [str(TINY), "--simulate", "0"], ["--simulate", "'0'"]),
    ("--simulate abc", lambda t: [str(TINY), "--simulate", "abc"], ["--simulate", "'abc'"]),
    ("unknown robot key", lambda t: [str(TINY), "--simulate", "2", "--robot",
                                     str(bad_robot(t))], ["bad_robot.yaml", "'fvo'"]),
    ("robot key without --simulate", lambda t: [str(TINY), "--robot", str(bad_robot(t))],
     ["bad_robot.yaml", "'fvo'"]),
    ("no enclosed building", lambda t: [str(open_plan(t)), "--resolution", "0.5",
                                        "--simulate", "2"], ["open.png", "no enclosed"]),
    ("--jobs 0", lambda t: [str(TINY), "--simulate", "2", "--jobs", "0"], ["--jobs"]),
    ("--max-runs 0", lambda t: [str(TINY), "--simulate", "auto", "--max-runs", "0"],
     ["--max-runs"]),
]


@pytest.mark.parametrize("case, arguments, words", BAD_INPUTS, ids=[c[0] for c in BAD_INPUTS])
def test_bad_input_is_one_line_exit_2_and_nothing_written(tmp_path, case, arguments, words):
    argv = [*arguments(tmp_path), "--out", str(tmp_path / "data"), "--no-progress"]
    if "--simulate" not in argv:
        argv = argv[:-3]  # no simulation options without --simulate
    before = sorted(tmp_path.rglob("*"))
    code, _, err = call(argv)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and "Traceback" not in err, err
    assert all(word in lines[0] for word in words), lines[0]
    assert sorted(tmp_path.rglob("*")) == before


def test_simulation_options_need_simulate(tmp_path):
    code, _, err = call([str(TINY), "--out", str(tmp_path / "data")])
    assert code == 2 and "--out needs --simulate" in err
    assert not (tmp_path / "data").exists()


def test_setup_note_names_what_differs_from_the_training_runs():
    """The robot-independent set-up (GMapping compute-time emulation, stop rule, metric)
    of the simulated runs against the card's: a note naming the parts that differ."""
    from slam_predict.cli.predict_simulate import setup_note

    card = {"config_hashes": {"slam_compute": ["85871b493ac8"], "stop": ["5fb6e3e0550b"],
                              "gmapping": ["aaa"]}}
    same = [{"config_hashes": {"slam_compute": "85871b493ac8", "stop": "5fb6e3e0550b",
                               "gmapping": "bbb"}}]          # GMapping changes with the robot
    assert setup_note(same, card) is None
    missing = [{"config_hashes": {"stop": "5fb6e3e0550b"}}]   # collect.yaml: no emulation
    note = setup_note(missing, card)
    assert note.startswith("the simulated runs' slam_compute configuration differs")
    assert "--settings" in note
    assert setup_note([], card) is None and setup_note(missing, None) is None
