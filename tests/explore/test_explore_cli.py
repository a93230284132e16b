"""``slam-predict explore``: a short run on an image plan, and one-line errors with exit 2."""
from __future__ import annotations

import json

import numpy as np
import pytest
from PIL import Image

from slam_predict.cli.main import main


@pytest.fixture()
def room_png(tmp_path):
    img = np.zeros((80, 120), np.uint8)
    img[4:76, 4:116] = 255
    img[4:50, 60:63] = 0                      # a half wall
    path = tmp_path / "room.png"
    Image.fromarray(img).save(path)
    return path


def test_explore_writes_json_and_png(room_png, tmp_path, capsys):
    out = tmp_path / "out"
    code = main(["explore", str(room_png), "--resolution", "0.05", "--seed", "3", "--out",
                 str(out), "--max-sim-time", "15", "--start", "1.0", "0.0", "90"])
    assert code == 0
    summary = json.loads((out / "explore.json").read_text())
    assert summary["seed"] == 3 and summary["map_source"] == "perfect"
    assert summary["start_pose"][:2] == [1.0, 0.0]
    assert summary["sim_duration_s"] <= 15.0 + 1e-6
    assert 0.0 < summary["coverage"] <= 1.0
    assert (out / "explore.png").read_bytes()[:4] == b"\x89PNG"
    assert "coverage" in capsys.readouterr().out


@pytest.mark.parametrize("args,needle", [
    (["missing.png", "--resolution", "0.05"], "missing.png"),
    (["{png}", "--resolution", "0.05", "--max-sim-time", "0"], "--max-sim-time"),
    (["{png}"], "resolution"),
    (["{png}", "--resolution", "0.05", "--start", "100", "100"], "outside the map"),
    (["{png}", "--resolution", "0.05", "--config-dir", "{tmp}/nope"], "config folder"),
])
def test_bad_input_is_one_line_and_exit_2(room_png, tmp_path, capsys, args, needle):
    args = [a.format(png=room_png, tmp=tmp_path) for a in args]
    code = main(["explore", *args, "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2
    assert needle in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "o").exists()


def test_output_that_is_a_file_is_refused(room_png, tmp_path, capsys):
    target = tmp_path / "file.txt"
    target.write_text("x")
    code = main(["explore", str(room_png), "--resolution", "0.05", "--out", str(target)])
    assert code == 2 and "not a folder" in capsys.readouterr().err


def test_bad_config_value_is_reported(room_png, tmp_path, root, capsys):
    cfg = tmp_path / "cfg"
    cfg.mkdir()
    for name in ("costmap_common.yaml", "global_costmap.yaml", "local_costmap.yaml",
                 "base_local_planner.yaml", "explore.yaml", "robot.yaml", "closed_loop.yaml"):
        (cfg / name).write_text((root / "config" / name).read_text())
    (cfg / "move_base.yaml").write_text("controller_frequncy: 10.0\n")
    code = main(["explore", str(room_png), "--resolution", "0.05", "--out", str(tmp_path / "o"),
                 "--config-dir", str(cfg)])
    err = capsys.readouterr().err
    assert code == 2 and "controller_frequency" in err and "move_base.yaml" in err
