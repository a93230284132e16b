"""``slam-predict predict`` (and ``scripts/predict``) with the shipped models: output, JSON
schema, and one-line errors for bad inputs."""
from __future__ import annotations

import json
import math
import shutil
import subprocess
import sys

import cv2
import numpy as np
import pytest

from slam_predict.cli.main import main

COMPONENTS = {"trans_mean": "m", "trans_std": "m", "rot_mean": "rad", "rot_std": "rad"}
SHIPPED_WORLD = "worlds/office_150.world"


@pytest.fixture(scope="module")
def models(root):
    folder = root / "models"
    for name in ("thesis-realistic", "thesis-optimistic"):
        assert (folder / name / "card.json").is_file(), f"shipped model {name} missing"
    return folder


def predict_json(root, capsys, *argv):
    assert main(["predict", *argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def check_schema(result: dict, components=tuple(COMPONENTS)) -> None:
    """The documented --json schema (docs/learning.md)."""
    assert isinstance(result["world"], str) and isinstance(result["model_store"], str)
    assert result["setting"] in ("realistic", "optimistic")
    assert 0 < result["confidence"] < 1
    assert isinstance(result["warnings"], list)
    assert all(isinstance(w, str) for w in result["warnings"])
    assert all(isinstance(v, float) for v in result["features"].values())
    for comp in components:
        entry = result[comp]
        assert entry["unit"] == COMPONENTS[comp]
        assert entry["model"].startswith(result["model_store"] + "/")
        if entry["status"] == "no_model":  # best model's evaluation R² ≤ 0
            assert set(entry) == {"status", "value", "low", "high", "model", "unit", "r2"}
            assert entry["value"] is None and entry["r2"] <= 0
            continue
        assert set(entry) == {"status", "value", "low", "high", "model", "unit", "raw_value",
                              "raw_low", "raw_high"}
        assert all(isinstance(entry[k], float) and math.isfinite(entry[k])
                   for k in ("raw_value", "raw_low", "raw_high"))
        if entry["status"] == "below_range":
            assert entry["value"] is None and entry["raw_value"] <= 0
            continue
        assert entry["status"] == "ok"
        assert all(isinstance(entry[k], float) and math.isfinite(entry[k])
                   for k in ("value", "low", "high"))
        assert 0.0 <= entry["low"] <= entry["value"] <= entry["high"]
        assert entry["low"] < entry["high"]
    for comp in set(COMPONENTS) - set(components):
        assert comp not in result


def test_shipped_world_json(root, models, capsys, monkeypatch):
    """office_150 is smaller than every training building: the prediction is an extrapolation,
    kept non-negative and flagged; office_500 lies inside the training range."""
    monkeypatch.chdir(root)
    result = predict_json(root, capsys, SHIPPED_WORLD)
    check_schema(result)
    assert result["setting"] == "realistic" and result["world"] == "office_150"
    assert result["model_store"] == "thesis-realistic"     # the default (own-realistic: -1)
    assert result["trans_mean"]["status"] == "below_range" or \
        0.0 < result["trans_mean"]["value"] < 2.0
    assert any("extrapolates" in w and "building_area" in w for w in result["warnings"])
    result = predict_json(root, capsys, "worlds/office_500.world")
    check_schema(result)
    assert 0.05 < result["trans_mean"]["value"] < 1.0


def test_text_output_lists_four_components_with_units(root, models, capsys, monkeypatch):
    monkeypatch.chdir(root)
    assert main(["predict", SHIPPED_WORLD, "--thesis-setting", "optimistic"]) == 0
    out = capsys.readouterr().out
    for comp in COMPONENTS:
        assert comp in out
    assert "90 % interval" in out and " m (" in out and " rad = " in out and " deg" in out
    assert "thesis-optimistic/" in out


def test_a_model_from_a_fitted_chain_says_so(root, models, capsys, monkeypatch):
    """own-realistic learnt from runs with a fitted map-rebuild cost and compute level: --json
    names both and the text says they are fitted; the seed study's own model has none."""
    monkeypatch.chdir(root)
    keys = ["slam_compute.rebuild_s_per_line_cell", "slam_compute.cpu_factor"]
    own = predict_json(root, capsys, "worlds/office_500.world", "--model", "own-realistic")
    assert sorted(own["fitted_settings"]) == sorted(keys)
    assert all("fitted on the 17 'fit' buildings" in own["fitted_settings"][k]
               or "chosen on the 17 'fit' buildings" in own["fitted_settings"][k] for k in keys)
    assert predict_json(root, capsys, "worlds/office_500.world")["fitted_settings"] == {}
    assert main(["predict", "worlds/office_500.world", "--model", "own-realistic"]) == 0
    lines = [line for line in capsys.readouterr().out.splitlines() if line.startswith("fitted:")]
    assert len(lines) == len(keys)
    assert all(k in line and "not measured" in line for k, line in zip(keys, lines, strict=True))


def test_ipa_map_with_resolution(shared_data, models, capsys):
    plan = shared_data / "floorplans" / "ipa" / "lab_c_scan.png"
    result = predict_json(None, capsys, str(plan), "--resolution", "0.05")
    check_schema(result)
    one = predict_json(None, capsys, str(plan), "--resolution", "0.05", "--component",
                       "rot_std")
    check_schema(one, ("rot_std",))
    assert one["rot_std"] == result["rot_std"]


def test_rosrun_script_prints_all_components(root, models):
    proc = subprocess.run([sys.executable, str(root / "scripts" / "predict"), SHIPPED_WORLD,
                           "__name:=predict"], cwd=root, capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert all(comp in proc.stdout for comp in COMPONENTS)


def error_of(capsys, *argv) -> str:
    code = main(["predict", *argv])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1, err
    assert "Traceback" not in err
    return err


def test_missing_model(root, models, capsys):
    err = error_of(capsys, str(root / SHIPPED_WORLD), "--model", "thesis-realistc")
    assert "no model named 'thesis-realistc'" in err and "did you mean 'thesis-realistic'" in err


def test_corrupt_model(root, models, tmp_path, capsys):
    copy = tmp_path / "broken"
    shutil.copytree(models / "thesis-realistic", copy)
    (copy / "trans_mean.joblib").write_bytes(b"\x80garbage")
    err = error_of(capsys, str(root / SHIPPED_WORLD), "--model", str(copy))
    assert "trans_mean.joblib: corrupt model file" in err


def test_plan_without_scale(tmp_path, models, capsys):
    image = np.full((60, 80), 255, np.uint8)
    image[[0, -1], :] = 0
    image[:, [0, -1]] = 0
    cv2.imwrite(str(tmp_path / "plan.png"), image)
    err = error_of(capsys, str(tmp_path / "plan.png"))
    assert "plan.png" in err and "--resolution" in err


def test_unknown_component(root, models, capsys):
    err = error_of(capsys, str(root / SHIPPED_WORLD), "--component", "rot_sdt")
    assert "unknown component 'rot_sdt'" in err and "did you mean 'rot_std'" in err


def test_world_and_resolution_exclusive(root, capsys):
    err = error_of(capsys, "x.png", "--world", str(root / SHIPPED_WORLD), "--resolution", "0.05")
    assert "either --world or --resolution" in err


def test_png_with_world_takes_scale_and_start_from_the_world(root, models, capsys,
                                                             monkeypatch):
    monkeypatch.chdir(root)
    direct = predict_json(root, capsys, SHIPPED_WORLD, "--component", "trans_mean")
    via_png = predict_json(root, capsys, "worlds/office_150.png", "--world", SHIPPED_WORLD,
                           "--component", "trans_mean")
    assert via_png["trans_mean"]["value"] == pytest.approx(direct["trans_mean"]["value"],
                                                           rel=0.02)


def test_named_model_uses_its_own_setting(root, models, capsys, monkeypatch):
    monkeypatch.chdir(root)
    result = predict_json(root, capsys, SHIPPED_WORLD, "--model", "thesis-optimistic",
                          "--component", "trans_mean")
    assert result["setting"] == "optimistic"
    err = error_of(capsys, SHIPPED_WORLD, "--model", "thesis-optimistic", "--thesis-setting",
                   "realistic")
    assert "trained for the optimistic setting, not realistic" in err
