"""``slam-predict features``: output formats, overlay, path, and bad input (one line, exit 2)."""
from __future__ import annotations

import json

import cv2
import numpy as np
import pytest

from slam_predict.cli.main import main
from slam_predict.features.vector import REGISTRY

from .plans import corridor_with_rooms


@pytest.fixture(scope="module")
def plan_png(tmp_path_factory):
    path = tmp_path_factory.mktemp("plans") / "comb.png"
    world = corridor_with_rooms(3).world()
    cv2.imwrite(str(path), np.where(world.occupied, 0, 255).astype(np.uint8))
    return path


def _run(args, capsys):
    code = main(["features", *map(str, args)])
    out, err = capsys.readouterr()
    return code, out, err


def test_json_output(plan_png, capsys):
    code, out, err = _run([plan_png, "--resolution", "0.05", "--json"], capsys)
    assert code == 0, err
    values = json.loads(out)
    assert list(values) == REGISTRY.names()
    assert values["num_spaces"] == 4
    assert values["voronoi_traversal_distance"] > 0


def test_table_overlay_and_path(plan_png, tmp_path, capsys):
    overlay, path = tmp_path / "out" / "o.png", tmp_path / "p.csv"
    code, out, err = _run([plan_png, "--resolution", "0.05", "--overlay", overlay, "--path", path,
                           "--start", "0", "-1.8", "90", "--mode", "thesis_compatible"], capsys)
    assert code == 0, err
    assert "voronoi_traversal_distance" in out and " m\n" in out
    picture = cv2.imread(str(overlay))
    assert picture is not None and picture.shape[0] > 100
    lines = path.read_text().splitlines()
    assert lines[0] == "x_m,y_m" and len(lines) > 2


def test_world_option(plan_png, tmp_path, capsys):
    world = tmp_path / "comb.world"
    world.write_text('define floorplan model ( obstacle_return 1 )\n'
                     'floorplan( bitmap "comb.png" size [15.8 7.6 1] pose [0 0 0 0] )\n'
                     'position( name "robot" pose [0 -1.8 0 0] )\n')
    (tmp_path / "comb.png").write_bytes(plan_png.read_bytes())
    code, out, err = _run([plan_png, "--world", world, "--json"], capsys)
    assert code == 0, err
    assert json.loads(out)["num_spaces"] == 4


def test_list(capsys):
    code, out, _ = _run(["--list"], capsys)
    assert code == 0 and "[voronoi_traversal]" in out and "voronoi_traversal_distance (m)" in out


@pytest.mark.parametrize("args, message", [
    (["missing.png", "--resolution", "0.05"], "missing.png: plan not found"),
    (["{plan}"], "resolution"),
    (["{plan}", "--resolution", "0.05", "--world", "{plan}"], "either --world or --resolution"),
    (["{plan}", "--resolution", "0.05", "--overlay", "{tmp}/o.jpg"], "overlay must be a .png"),
    (["{plan}", "--resolution", "0.05", "--config", "{tmp}/bad.yaml"], "did you mean 'mode'"),
    (["{plan}", "--resolution", "0.05", "--start", "500", "0"], "outside the map"),
    ([], "PLAN is required"),
    (["{plan}", "--resolution", "0.05", "--config", "{tmp}/top.yaml"],
     "unknown config key 'featurse_extra' (did you mean 'features'?)"),
    (["{plan}", "--resolution", "0.05", "--config", "{tmp}/deep.yaml"],
     "unknown config key 'sourec' in 'features.rooms' (did you mean 'source'?)"),
    (["{plan}", "--resolution", "0.05", "--config", "{tmp}/flat.yaml"],
     "unknown config key 'mdoe' (did you mean 'mode'?)"),
    (["{plan}", "--resolution", "5.0"], "is larger than any building"),
    (["{tmp}/noise.png", "--resolution", "0.05"], "no Voronoi graph and no rooms"),
])
def test_bad_input(args, message, plan_png, tmp_path, capsys):
    (tmp_path / "bad.yaml").write_text("features:\n  mod: documented\n")
    (tmp_path / "top.yaml").write_text("features:\n  mode: documented\nfeaturse_extra: 1\n")
    (tmp_path / "deep.yaml").write_text("features:\n  rooms:\n    sourec: segment\n")
    (tmp_path / "flat.yaml").write_text("mdoe: documented\n")  # no section: read as one
    noise = np.random.default_rng(0).random((200, 200)) > 0.5
    cv2.imwrite(str(tmp_path / "noise.png"), noise.astype(np.uint8) * 255)
    args = [a.format(plan=plan_png, tmp=tmp_path) for a in args]
    code, out, err = _run(args, capsys)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], err
    assert not (tmp_path / "o.jpg").exists()


def test_force_accepts_an_implausible_scale(plan_png, capsys):
    code, out, err = _run([plan_png, "--resolution", "5.0", "--json", "--force"], capsys)
    assert code == 0, err
    assert json.loads(out)["building_area"] > 100_000


def test_the_shipped_config_passes_the_strict_loader(root, capsys, plan_png):
    code, _, err = _run([plan_png, "--resolution", "0.05", "--config",
                         root / "config" / "features.yaml", "--json"], capsys)
    assert code == 0, err
