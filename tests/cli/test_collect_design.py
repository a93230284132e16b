"""`slam-predict design` + `collect --design`: two short tiny-world runs, each with the robot of
its design point; the resume, a changed design and bad combinations are refused."""
import json
import math

import pytest
from robot_runs import ROOT, TINY, short_settings

from slam_predict.cli.main import main
from slam_predict.collect.robot_design import load_design


@pytest.fixture
def design_file(tmp_path):
    path = tmp_path / "design.yaml"
    assert main(["design", str(TINY), "--configs", "3", "--points-per-world", "2",
                 "--replicates", "1", "--seed", "4", "--out", str(path)]) == 0
    return path


def test_each_run_gets_its_design_robot(tmp_path, design_file, capsys):
    settings = short_settings(tmp_path)
    out = tmp_path / "data"
    args = ["collect", str(TINY), "--out", str(out), "--settings", str(settings),
            "--design", str(design_file), "--no-progress"]
    assert main(args) == 0, capsys.readouterr().err
    design = load_design(design_file)
    for index in range(2):
        record = json.loads((out / "tiny" / f"run_{index:03d}" / "run.json").read_text())
        point = design.run_point("tiny", index)
        assert record["design"] == point
        laser, odom = record["sensor"]["laser"], record["sensor"]["odom"]
        assert laser["range_max"] == point["range_max"]
        assert math.isclose(laser["fov"], math.radians(point["fov"]), rel_tol=1e-6)
        assert laser["samples"] == round(point["fov"] / 0.5) + 1
        assert odom["error"][0] == pytest.approx(0.01 * point["odom_xy_scale"])
        assert odom["error"][2] == pytest.approx(math.radians(2.0) * point["odom_yaw_scale"])
    summary = (out / "summary.csv").read_text().splitlines()
    assert len(summary) == 3                       # one row per (world, robot): two points
    assert main(args) == 0                         # resume: nothing left to do
    assert "0 runs done" in capsys.readouterr().out
    # a fresh clone has the run.json files but not campaign.json: adopted, each run checked
    # against the settings with its own design robot
    (out / "campaign.json").unlink()
    assert main(args) == 0, capsys.readouterr().err
    assert "0 runs done" in capsys.readouterr().out
    assert json.loads((out / "campaign.json").read_text())["adopted"]["runs"] == 2
    (out / "campaign.json").unlink()
    run_json = out / "tiny" / "run_001" / "run.json"
    original = run_json.read_text()
    record = json.loads(original)
    record["config_hashes"]["sim"] = "x"
    run_json.write_text(json.dumps(record))
    assert main(args) == 2                         # ... and a run of other settings refused
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "run_001/run.json" in err[0] and "(sim config" in err[0]
    assert not (out / "campaign.json").exists()
    run_json.write_text(original)
    assert main(args) == 0
    capsys.readouterr()
    design_file.write_text(design_file.read_text().replace("seed: 4", "seed: 5"))
    assert main(args) == 2
    assert "design file differs" in capsys.readouterr().err


def test_bad_design_combinations(tmp_path, design_file, capsys):
    out = str(tmp_path / "data")
    lds = str(ROOT / "config" / "robots" / "lds_360_3p5.yaml")
    other = ROOT / "worlds" / "office_150.world"
    cases = [
        (["--design", str(design_file), "--robot", lds], "excludes --robot"),
        (["--design", str(design_file), "--runs", "3"], "--runs must be 1..2"),
        (["--design", str(design_file), "--runs", "auto"], "--runs must be 1..2"),
        (["--design", str(tmp_path / "missing.yaml")], "not found"),
    ]
    for extra, message in cases:
        assert main(["collect", str(TINY), "--out", out, *extra]) == 2
        err = capsys.readouterr().err
        assert message in err and err.count("\n") == 1, err
    assert main(["collect", str(other), "--out", out, "--design", str(design_file)]) == 2
    assert "not in the design" in capsys.readouterr().err
    assert not (tmp_path / "data").exists()


def test_design_command_refuses_bad_counts(tmp_path, capsys):
    out = str(tmp_path / "d.yaml")
    for extra, message in [(["--configs", "0"], "--configs"),
                           (["--configs", "2", "--points-per-world", "3"], "exceeds"),
                           (["--fov", "300", "200"], "LOW must be <= HIGH"),
                           (["--range", "-5", "-1"], "range_max")]:
        assert main(["design", str(TINY), "--out", out, *extra]) == 2
        err = capsys.readouterr().err
        assert message in err and err.count("\n") == 1, err
    assert not (tmp_path / "d.yaml").exists()
    assert main(["design", str(TINY), "--out", out]) == 0
    assert main(["design", str(TINY), "--out", out, "--seed", "1"]) == 2   # no --force
    assert "--force" in capsys.readouterr().err


@pytest.mark.parametrize("extra, words", [
    (["--fov", "3", "6.28"], ["looks like radians", "from --fov 3 6.28"]),
    (["--range", "1000", "12000"], ["beyond any planar laser", "if it was mm",
                                    "from --range 1000 12000"]),
    (["--angle-step", "20"], ["coarser than any planar laser", "from --angle-step 20"])])
def test_design_bounds_no_laser_has_are_refused_unless_force(tmp_path, capsys, extra, words):
    out = tmp_path / "d.yaml"
    args = ["design", str(TINY), "--configs", "3", "--points-per-world", "1", "--out", str(out),
            *extra]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and all(word in err for word in words), err
    assert "--force" in err and not out.exists()
    assert main([*args, "--force"]) == 0
    assert load_design(out).configs


def test_collect_refuses_a_design_with_a_laser_no_robot_has(tmp_path, capsys):
    design = tmp_path / "d.yaml"
    assert main(["design", str(TINY), "--configs", "2", "--points-per-world", "1",
                 "--replicates", "1", "--range", "2000", "4000", "--force",
                 "--out", str(design)]) == 0
    out = tmp_path / "data"
    assert main(["collect", str(TINY), "--design", str(design), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and str(design) in err and "if it was mm" in err, err
    assert not out.exists()


def test_the_default_base_robot_is_found_from_any_folder(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["design", str(TINY), "--configs", "2", "--points-per-world", "1",
                 "--out", "d.yaml"]) == 0
    assert load_design(tmp_path / "d.yaml").base.name == "seed_realistic"
    assert "2 configurations over 1 world, 1 per world x 2 replicates" in capsys.readouterr().out
