"""The learning section with a robot-aware model folder: card, evaluation table and
partial-dependence plots; a plan-only folder beside it is shown exactly as before."""
from __future__ import annotations

import base64
import html
import json
import shutil

import cv2
import numpy as np
import pytest

from slam_predict.learn.robot.inputs import ROBOT_INPUTS
from slam_predict.learn.robot.predict import RobotModel
from slam_predict.report.build import build_report
from slam_predict.report.robot_models import curves

from .test_learning import MODEL, mid_range_features

COMPONENTS = ("trans_mean", "trans_std", "rot_mean", "rot_std")


@pytest.fixture(scope="module")
def models(tmp_path_factory, model_dir, robot_models_dir):
    """A models folder with the plan-only test model and the synthetic own-robots."""
    folder = tmp_path_factory.mktemp("mixed")
    shutil.copytree(model_dir, folder / MODEL)
    shutil.copytree(robot_models_dir / "own-robots", folder / "own-robots")
    return folder


@pytest.fixture(scope="module")
def pages(campaign_dir, models, model_dir):
    """(page with both folders, page with the plan-only folder alone) as HTML text."""
    return (build_report(campaign_dir, models, feature_fn=mid_range_features),
            build_report(campaign_dir, model_dir, feature_fn=mid_range_features))


def test_partial_dependence_figures_of_every_component(pages, parse):
    page = parse(pages[0])
    assert "Model own-robots" in page.headings
    assert "Partial dependence on the robot (own-robots)" in page.headings
    alts = [img["alt"] for img in page.images]
    for component in COMPONENTS:
        assert f"partial dependence of {component}, model own-robots" in alts
    png = next(img["src"] for img in page.images
               if img["alt"] == "partial dependence of trans_mean, model own-robots")
    image = cv2.imdecode(np.frombuffer(base64.b64decode(png.split(",", 1)[1]), np.uint8),
                         cv2.IMREAD_COLOR)
    assert image.shape[0] > 500 and image.shape[1] > 800     # 2 × 2 panels


def test_card_tables_of_the_robot_aware_model(pages, parse, models):
    page = parse(pages[0])
    card = json.loads((models / "own-robots" / "card.json").read_text())
    ranges = page.rows_by_first(page.table(["input", "kind", "unit", "training range"]))
    assert ranges["laser_range_max_m"]["unit"] == "m"
    assert ranges["laser_range_max_m"]["training range"] == "3.5 – 30"
    assert ranges["laser_fov_deg"]["design bounds"] == "180 – 360"
    assert ranges["building_area"]["kind"] == "plan"
    table = page.table(["component", "unit", "model", "protocol"])
    assert {r[2] for r in table["rows"]} == {"elasticnet", "gradient_boosting"}
    assert len(table["rows"]) == 8            # 4 components × 2 kinds, no evaluation stored
    text = html.unescape(pages[0])
    assert "30 m (range input = min(laser range, GMapping's maxUrange))" in text
    assert card["max_urange_m"] == 30.0


def test_curves_span_the_training_range_and_stop_at_maxurange(models):
    model = RobotModel.load(models / "own-robots")
    lines = curves(model, "trans_mean")
    assert list(lines) == list(ROBOT_INPUTS)
    reach = lines["laser_range_max_m"]
    assert reach["grid"][0] < 3.5 and reach["grid"][-1] == 30.0 and reach["cap"] == 30.0
    assert reach["trained"] == [3.5, 30.0] and len(reach["configs"]) == 6
    fov = lines["laser_fov_deg"]
    assert fov["grid"][0] < 180.0 < 360.0 < fov["grid"][-1] and fov["cap"] is None
    assert lines["odom_xy_error"]["grid"][0] == 0.0
    grid, values = model.partial_dependence("trans_mean", "laser_range_max_m", 25,
                                            (reach["grid"][0], 30.0))
    assert np.array_equal(grid, reach["grid"]) and np.array_equal(values, reach["values"])
    assert reach["xlabel"] == "laser_range_max_m [m]"


def test_plan_only_folder_is_shown_as_before(pages, parse):
    """The plan-only model's sections are the same bytes with or without the robot-aware
    folder beside it, and a page of plan-only folders has no partial-dependence plot."""
    both, alone = pages
    start = alone.index(f'<section id="model-{MODEL}">')
    end = alone.rindex("</section>")          # the learning section's end
    assert alone[start:end] in both
    assert both.index('<section id="model-own-robots">') < both.index(
        f'<section id="model-{MODEL}">')
    page = parse(alone)
    assert not any("partial dependence" in img["alt"] for img in page.images)
    assert not any(h.startswith("Partial dependence") for h in page.headings)


def robot_features(world: str, card: dict) -> dict:
    """mid_range_features for plan-only cards; for a robot-aware card its plan features
    inside their training ranges and a sight-line curve (no plan needed)."""
    from slam_predict.features.sightline import curve_columns

    if "input_ranges" not in card:
        return mid_range_features(world, card)
    share = 0.3 if world == "alpha" else 0.7
    out = {name: low + share * (high - low)
           for name, (low, high) in card["input_ranges"].items() if name in card["features"]}
    columns = curve_columns()
    out.update(zip(columns, np.linspace(0.9, 0.0, len(columns)), strict=True))
    return out


def test_robot_aware_predictions_use_each_runs_recorded_robot(campaign_dir, models, tmp_path,
                                                              parse):
    """Runs recorded with the LDS robot: the robot-aware model predicts per world × robot from
    that robot (same numbers as RobotModel.predict with inputs_from_sensor), with the failure
    probability beside it; the plan-only model's predictions say that they ignore the robot."""
    from slam_predict.learn.robot.inputs import inputs_from_sensor

    from .test_robots_and_spreads import LDS, with_robot

    data = with_robot(campaign_dir, tmp_path)
    page = parse(build_report(data, models, feature_fn=robot_features))
    heading = "Predictions of own-robots for this campaign's runs, per robot"
    assert heading in page.headings
    robot = "laser 3.5 m, 360°, 360 beams; odometry fixed 0.01, 0.01 m/m, 2 °/rad"
    table = page.table(["world", "runs", "component"], section=heading)
    rows = [dict(zip(table["header"], row, strict=True)) for row in table["rows"]]
    assert {r["world"] for r in rows} == {f"alpha [{robot}]", f"beta [{robot}]"}
    model = RobotModel.load(models / "own-robots")
    card = json.loads((models / "own-robots" / "card.json").read_text())
    expected = model.predict(robot_features("alpha", card),
                             inputs_from_sensor(LDS, None, model.max_urange_m))
    alpha = {r["component"]: r for r in rows if r["world"].startswith("alpha")}
    assert alpha["trans_mean"]["predicted"] == f"{expected['trans_mean']['value']:.4f}"
    assert alpha["trans_mean"]["runs"] == "3"
    failure = page.table(["world [robot]", "runs"], section=heading)
    assert len(failure["rows"]) == 2
    metrics = page.table(["component", "unit", "model", "protocol"])
    assert metrics["header"][-1] == "monotone in the robot"
    for row in metrics["rows"]:
        check = card["components"][row[0]]["models"][row[2]]["monotone"]
        assert row[-1] == "yes" if check["passed"] else row[-1].startswith("no (")
    assert page.table(["predicted p", "runs", "mean predicted", "observed failures"])
    assert any("plan-only model does not take the robot into account" in n and robot in n
               for n in page.notes)
