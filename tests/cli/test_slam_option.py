"""``--slam`` on predict, explore, collect and slam run: karto (and its other name slam_toolbox)
runs end to end; an unknown name or a bad Karto parameter is one line, exit 2, nothing written."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from slam_predict.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
TINY = ROOT / "worlds" / "tiny.world"
ACES = ROOT.parent / "shared" / "data" / "slam_inputs" / "aces.log.gz"


def files_under(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


def karto_settings(tmp_path: Path, params: str, base: str = "collect_karto.yaml",
                   gate: str = "sync", cpu_factor: float = 1.0) -> Path:
    """Settings extending the shipped ``base`` with Karto parameters ``params`` (YAML lines)."""
    (tmp_path / "karto.yaml").write_text((ROOT / "config" / "karto.yaml").read_text()
                                         .replace("scan_gate: sync", f"scan_gate: {gate}")
                                         .replace("cpu_factor: 1.0", f"cpu_factor: {cpu_factor}")
                                         + params)
    path = tmp_path / "s.yaml"
    path.write_text(f"extends: {ROOT / 'config' / base}\nslam:\n  type: karto\n"
                    f"  params: karto.yaml\nstop:\n  max_sim_time_s: 20.0\n")
    return path


def config_dir_with(tmp_path: Path, karto_lines: str, old: str = "", new: str = "") -> Path:
    folder = tmp_path / "cfg"
    folder.mkdir()
    for path in (ROOT / "config").glob("*.yaml"):
        (folder / path.name).write_text(path.read_text())
    text = (ROOT / "config" / "karto.yaml").read_text()
    (folder / "karto.yaml").write_text((text.replace(old, new) if old else text) + karto_lines)
    return folder


BAD = [
    ("predict: karto has no model", lambda t: ["predict", str(TINY), "--slam", "karto"],
     ["--slam karto", "no model", "slam-predict collect", "--slam karto"]),
    ("predict: slam_toolbox is karto", lambda t: ["predict", str(TINY), "--slam", "slam_toolbox"],
     ["--slam karto", "no model"]),
    ("predict: unknown", lambda t: ["predict", str(TINY), "--slam", "karot"],
     ["--slam karot", "unknown SLAM back-end", "did you mean 'karto'"]),
    ("explore: unknown", lambda t: ["explore", str(TINY), "--slam", "cartographer", "--out",
                                    str(t / "o")], ["--slam cartographer", "unknown"]),
    ("explore: unknown karto key", lambda t: [
        "explore", str(TINY), "--slam", "slam_toolbox", "--out", str(t / "o"), "--config-dir",
        str(config_dir_with(t, "minimum_travel_distnce: 0.3\n"))],
     ["karto.yaml", "minimum_travel_distnce", "did you mean"]),
    ("explore: contradicts --map-source", lambda t: [
        "explore", str(TINY), "--slam", "karto", "--map-source", "gmapping", "--out",
        str(t / "o")], ["--slam karto", "--map-source gmapping"]),
    ("collect: negative resolution", lambda t: [
        "collect", str(TINY), "--slam", "karto", "--settings",
        str(karto_settings(t, "resolution: -0.05\n")), "--out", str(t / "d"), "--no-progress"],
     ["karto.yaml", "resolution"]),
    ("collect: wrong type", lambda t: [
        "collect", str(TINY), "--settings", str(karto_settings(t, "scan_buffer_size: many\n")),
        "--out", str(t / "d"), "--no-progress"], ["karto.yaml", "scan_buffer_size"]),
    ("collect: settings of another back-end", lambda t: [
        "collect", str(TINY), "--slam", "karto", "--settings",
        str(ROOT / "config" / "collect.yaml"), "--out", str(t / "d"), "--no-progress"],
     ["collect.yaml", "slam.type is gmapping, not karto"]),
    ("collect: unknown", lambda t: ["collect", str(TINY), "--slam", "hector", "--out",
                                    str(t / "d"), "--no-progress"], ["--slam hector"]),
    ("slam run: unknown", lambda t: ["slam", "run", str(ACES), "--slam", "karot", "--out",
                                     str(t / "r")], ["--slam karot", "did you mean 'karto'"]),
    ("slam run: bad karto config", lambda t: [
        "slam", "run", str(ACES), "--slam", "karto", "--out", str(t / "r"), "--config",
        str(config_dir_with(t, "", "cpu_factor: 1.0", "cpu_factor: 0") / "karto.yaml")],
     ["karto.yaml", "async_cost.cpu_factor"]),
]


@pytest.mark.parametrize("case, arguments, words", BAD, ids=[c[0] for c in BAD])
def test_bad_slam_choice_is_one_line_exit_2_and_nothing_written(tmp_path, capsys, case,
                                                                arguments, words):
    argv = arguments(tmp_path)
    before = files_under(tmp_path)
    code = main(argv)
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert code == 2 and len(err) == 1, captured.err
    assert all(word in err[0] for word in words), err[0]
    assert files_under(tmp_path) == before


@pytest.mark.skipif(not ACES.is_file(), reason=f"no shared SLAM log {ACES}")
def test_slam_run_takes_slam_toolbox_as_karto(tmp_path, capsys):
    assert main(["slam", "run", str(ACES), "--slam", "slam_toolbox", "--max-scans", "40",
                 "--out", str(tmp_path / "r")]) == 0
    assert capsys.readouterr().out.startswith("karto: ")


@pytest.mark.parametrize("gate", ["sync", "async"])
def test_a_karto_campaign_runs_end_to_end(tmp_path, capsys, gate):
    """collect --slam karto on the tiny world with settings that say slam.type: karto (the
    async node's real time on a machine 200 times slower than the reference)."""
    settings = karto_settings(tmp_path, "", gate=gate, cpu_factor=200.0)
    out = tmp_path / "data"
    code = main(["collect", str(TINY), "--slam", "slam_toolbox", "--settings", str(settings),
                 "--runs", "1", "--out", str(out), "--no-progress"])
    assert code == 0, capsys.readouterr().err
    record = json.loads((out / "tiny" / "run_000" / "run.json").read_text())
    assert record["slam"]["type"] == "karto"
    assert record["sim_duration_s"] >= 19.0
    if gate == "async":   # the scans arrive faster than the slow machine handles them
        assert record["slam_async"]["scans_dropped"] > 0
        assert record["slam_async"]["rebuilds"] >= 2
    else:
        assert "slam_async" not in record
    assert (out / "summary.csv").read_text().count("\n") == 2
