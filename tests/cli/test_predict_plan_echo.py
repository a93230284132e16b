"""`predict` says what it took from the plan (scale and where it came from, free area, start
pose) in text and JSON, and names no model beside "no model"."""
from __future__ import annotations

import json

import pytest

from slam_predict.cli.main import main


def predict_json(capsys, *argv):
    assert main(["predict", *argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_a_world_file_gives_scale_and_start(root, capsys):
    plan = predict_json(capsys, str(root / "worlds" / "office_500.world"))["plan"]
    assert plan["scale_m_per_px"] == 0.05 and plan["scale_from"] == "the .world's floorplan size"
    assert plan["start_from"] == "the plan" and plan["free_area_m2"] == pytest.approx(503, abs=1)
    assert main(["predict", str(root / "worlds" / "office_500.world")]) == 0
    text = capsys.readouterr().out.splitlines()
    assert text[1].startswith("plan: 0.05 m/px (the .world's floorplan size), free area 503 m²")


def test_an_image_with_resolution_and_start(shared_data, capsys):
    plan = predict_json(capsys, str(shared_data / "floorplans" / "ipa" / "office_a.png"),
                        "--resolution", "0.05")["plan"]
    assert plan["scale_from"] == "--resolution"
    assert plan["start_from"] == "the free cell of largest clearance"
    assert plan["free_area_m2"] == pytest.approx(1529.5, abs=0.1)


def test_a_layout_names_its_scale(shared_data, capsys):
    layout = sorted((shared_data / "floorplans" / "layouts").glob("*.xml"))[0]
    plan = predict_json(capsys, str(layout), "--force")["plan"]
    assert plan["scale_from"].startswith("the layout's <scale> (")


def test_no_model_name_beside_no_model(root, capsys):
    assert main(["predict", str(root / "worlds" / "office_500.world")]) == 0
    lines = [ln for ln in capsys.readouterr().out.splitlines() if "no model (" in ln]
    assert lines and all("[" not in ln for ln in lines)
