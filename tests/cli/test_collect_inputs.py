"""`slam-predict collect`: every input checked before any work, and campaign.json (a resume with
another seed or other settings is refused; folders without campaign.json are adopted)."""
import json
from pathlib import Path

import pytest

from slam_predict.cli.main import main
from slam_predict.collect import campaign
from slam_predict.collect.record import code_version
from slam_predict.collect.settings import load_settings
from slam_predict.collect.store import run_seed

ROOT = Path(__file__).resolve().parents[2]
TINY = ROOT / "worlds" / "tiny.world"
COLLECT_YAML = ROOT / "config" / "collect.yaml"


def files_under(folder: Path):
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


def write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


def settings_with(tmp_path: Path, body: str, name: str = "s.yaml") -> Path:
    return write(tmp_path / name, f"extends: {COLLECT_YAML}\n{body}")


def bad_world(tmp_path: Path, kind: str) -> Path:
    text = TINY.read_text()
    content = {"empty": "", "garbage": None, "syntax": "window( size [ 10 10 \n",
               "start_at_wall": text.replace("pose [ -3.75 -2.575 0 0 ]", "pose [ -2.3 0 0 0 ]")
               .replace('bitmap "tiny.png"', f'bitmap "{TINY.parent / "tiny.png"}"'),
               "unknown_keyword": text.replace("\nfloorplan\n", "\nflurplan\n"),
               "missing_bitmap": text.replace('bitmap "tiny.png"', 'bitmap "none.png"')}[kind]
    path = tmp_path / f"{kind}.world"
    if content is None:
        path.write_bytes(bytes(range(256)) * 3)
    else:
        path.write_text(content)
    return path


def bad_robot(tmp_path: Path, old: str, new: str) -> Path:
    """The LDS-01 class robot file with ``old`` replaced by ``new``."""
    text = (ROOT / "config" / "robots" / "lds_360_3p5.yaml").read_text()
    assert old in text
    path = tmp_path / "bad_robot.yaml"
    path.write_text(text.replace(old, new))
    return path


def with_robot(old: str, new: str):
    """Arguments (given tmp_path) collecting the tiny world with a spoilt robot file."""
    return lambda t: [str(TINY), "--robot", str(bad_robot(t, old, new))]


def with_settings(body: str):
    """Arguments (given tmp_path) collecting the tiny world with a settings file of ``body``."""
    return lambda t: [str(TINY), "--settings", str(settings_with(t, body))]


# (case, extra arguments given tmp_path, words the error line must hold)
BAD_INPUTS = [
    ("empty world", lambda t: [str(bad_world(t, "empty"))], ["empty.world"]),
    ("garbage world", lambda t: [str(bad_world(t, "garbage"))], ["garbage.world"]),
    ("syntax error world", lambda t: [str(bad_world(t, "syntax"))], ["syntax.world"]),
    ("unknown keyword world", lambda t: [str(bad_world(t, "unknown_keyword"))], ["flurplan"]),
    ("world bitmap missing", lambda t: [str(bad_world(t, "missing_bitmap"))],
     ["missing_bitmap.world"]),
    ("footprint on a wall at the start", lambda t: [str(bad_world(t, "start_at_wall"))],
     ["start_at_wall.world", "overlaps an obstacle"]),
    ("one bad world of two", lambda t: [str(TINY), str(bad_world(t, "empty"))], ["empty.world"]),
    ("negative max_snapshots", with_settings("stop:\n  max_snapshots: -5\n"),
     ["s.yaml", "max_snapshots"]),
    ("confidence out of range", with_settings("metric:\n  confidence: 1.5\n"), ["confidence"]),
    ("unknown nested key", with_settings("stop:\n  max_snapshot: 3\n"), ["s.yaml", "max_snapshot"]),
    ("unknown top-level key", with_settings("stpo:\n  max_snapshots: 3\n"), ["stpo"]),
    ("robot file missing", lambda t: [str(TINY), "--robot", str(t / "none.yaml")],
     ["none.yaml", "robot file not found"]),
    ("robot unknown key", with_robot("  fov: 360.0", "  fvo: 360.0"),
     ["bad_robot.yaml", "'fvo'", "did you mean 'fov'"]),
    ("robot negative range", with_robot("range_max: 3.5", "range_max: -3.5"),
     ["bad_robot.yaml", "laser.range_max", "> 0"]),
    ("robot fov over 360", with_robot("fov: 360.0", "fov: 400.0"),
     ["bad_robot.yaml", "laser.fov", "(0, 360]"]),
    ("robot slower than the planner", with_robot("max_vel_x: 0.85", "max_vel_x: 0.05"),
     ["bad_robot.yaml", "min_vel_x"]),
    ("--jobs 0", lambda t: [str(TINY), "--jobs", "0"], ["--jobs"]),
    ("--runs 0", lambda t: [str(TINY), "--runs", "0"], ["--runs"]),
    ("--max-runs 0", lambda t: [str(TINY), "--runs", "auto", "--max-runs", "0"], ["--max-runs"]),
]


@pytest.mark.parametrize("case, arguments, words", BAD_INPUTS, ids=[c[0] for c in BAD_INPUTS])
def test_bad_input_is_one_line_exit_2_and_nothing_written(tmp_path, capsys, case, arguments,
                                                          words):
    argv = ["collect", *arguments(tmp_path), "--out", str(tmp_path / "data"), "--no-progress"]
    before = files_under(tmp_path)
    code = main(argv)
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert code == 2 and len(err) == 1, captured.err
    assert "Traceback" not in captured.err
    assert all(word in err[0] for word in words), err[0]
    assert files_under(tmp_path) == before


def out_is_a_file(tmp_path):
    return write(tmp_path / "taken", "mine\n")


def out_under_a_file(tmp_path):
    return write(tmp_path / "plain", "mine\n") / "data"


def out_not_a_campaign(tmp_path):
    (tmp_path / "thesis").mkdir()
    write(tmp_path / "thesis" / "thesis.tex", "mine\n")
    return tmp_path / "thesis"


@pytest.mark.parametrize("make_out, words", [(out_is_a_file, ["taken", "is a file"]),
                                             (out_under_a_file, ["plain is a file"]),
                                             (out_not_a_campaign, ["thesis", "no campaign"])])
def test_bad_out_folder_is_refused_before_anything_starts(tmp_path, capsys, make_out, words):
    out = make_out(tmp_path)
    before = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    code = main(["collect", str(TINY), "--out", str(out), "--no-progress"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and all(w in err[0] for w in words), err
    assert {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()} == before


def test_unwritable_out_folder_is_refused(read_only_folder, capsys):
    out = read_only_folder / "data"
    code = main(["collect", str(TINY), "--out", str(out), "--no-progress"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "not writable" in err[0]
    assert not out.exists()


# -- campaign.json ----------------------------------------------------------------------------

def fake_record(world: str, index: int, seed: int, hashes) -> dict:
    """A run.json with what summary.csv and the campaign checks read."""
    return {"world": world, "run_index": index, "seed": seed, "config_hashes": hashes,
            "metric": {"trans_mean": 0.1 + index / 100, "rot_mean": 0.01,
                       "trans_sqr_mean": 0.02, "rot_sqr_mean": 1e-4},
            "distance_m": 50.0, "rotation_rad": 20.0, "coverage": 0.98,
            "sim_duration_s": 900.0}


def legacy_campaign(root: Path, runs: int, base_seed: int = 0, hashes=None) -> Path:
    """A campaign folder as collected before campaign.json existed: run.json files only."""
    hashes = hashes or load_settings().hashes()
    for index in range(runs):
        folder = root / "tiny" / f"run_{index:03d}"
        folder.mkdir(parents=True)
        record = fake_record("tiny", index, run_seed(base_seed, "tiny", index), hashes)
        (folder / "run.json").write_text(json.dumps(record))
    return root


def collect(out: Path, *extra: str) -> list:
    return ["collect", str(TINY), "--runs", "2", "--out", str(out), "--no-progress", *extra]


def test_legacy_folder_is_adopted_on_resume(tmp_path, capsys):
    out = legacy_campaign(tmp_path / "data", runs=2)
    assert main(collect(out)) == 0
    assert capsys.readouterr().out.startswith("0 runs done; summary:")
    recorded = json.loads((out / "campaign.json").read_text())
    assert recorded["base_seed"] == 0 and recorded["adopted"]["runs"] == 2
    assert recorded["config_hashes"] == load_settings().hashes()
    assert recorded["settings"]["stop"]["max_snapshots"] == load_settings().stop.max_snapshots
    assert main(collect(out)) == 0  # campaign.json now agrees


@pytest.mark.parametrize("extra, hashes, words", [
    (("--seed", "7"), None, ["run_000/run.json", "--seed 7"]),
    ((), {"sim": "x", "nav": "y"}, ["run_000/run.json", "nav", "sim"]),
])
def test_legacy_folder_of_another_configuration_is_refused(tmp_path, capsys, extra, hashes,
                                                           words):
    current = load_settings().hashes()
    out = legacy_campaign(tmp_path / "data", runs=2,
                          hashes=hashes and {**current, **hashes})
    before = files_under(out)
    assert main(collect(out, *extra)) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and all(w in err[0] for w in words), err
    assert files_under(out) == before


def campaign_folder(root: Path, settings=None, base_seed: int = 0) -> Path:
    """A campaign with campaign.json and its two runs done."""
    current = campaign.identity(load_settings(settings), base_seed, code_version())
    campaign.open_campaign(root, current)
    legacy_campaign(root, runs=2, base_seed=base_seed)
    return root


def test_resume_with_another_seed_or_settings_is_refused(tmp_path, capsys):
    out = campaign_folder(tmp_path / "data")
    recorded = (out / "campaign.json").read_text()
    assert main(collect(out, "--seed", "7")) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "campaign.json" in err[0] and "--seed 0, not --seed 7" in err[0]
    other = settings_with(tmp_path, "stop:\n  max_sim_time_s: 60.0\n")
    assert main(collect(out, "--settings", str(other))) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "stop.max_sim_time_s: 14400.0 -> 60.0" in err[0], err
    assert (out / "campaign.json").read_text() == recorded


def test_same_settings_in_another_file_resume(tmp_path, capsys):
    out = campaign_folder(tmp_path / "data")
    copy = settings_with(tmp_path, "# the same configuration, another file\n")
    assert main(collect(out, "--settings", str(copy))) == 0
    assert "0 runs done" in capsys.readouterr().out


def test_force_accepts_a_new_configuration_and_keeps_the_old_in_history(tmp_path, capsys):
    out = campaign_folder(tmp_path / "data")
    assert main(collect(out, "--seed", "7", "--force", "--runs", "1")) == 0
    recorded = json.loads((out / "campaign.json").read_text())
    assert recorded["base_seed"] == 7
    assert [h["base_seed"] for h in recorded["history"]] == [0]
    assert "--seed 7" in recorded["history"][0]["reason"]
    assert main(collect(out, "--seed", "7", "--runs", "1")) == 0   # the new one is the campaign's


def test_differences_name_key_paths():
    old = {"stop": {"a": 1, "b": [1, 2]}, "x": 1}
    new = {"stop": {"a": 2, "b": [1, 2], "c": 0}, "x": 1}
    assert campaign.differences(old, new) == ["stop.a: 1 -> 2", "stop.c: (absent) -> 0"]
    assert campaign.differences(old, old) == []
