"""The learning section: model cards, predictions next to measured values, damaged models."""
from __future__ import annotations

import html
import json
import math
import shutil

import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.learn.predict import predict_features
from slam_predict.learn.store import ModelStore
from slam_predict.report.build import build_report
from slam_predict.report.campaign import load_campaign
from slam_predict.report.predictions import SHIPPED_WORLDS, find_world_file

from .fake_campaign import ERRORS

MODEL = "thesis-realistic"


def mid_range_features(world: str, card: dict) -> dict:
    """A feature vector inside the training ranges, different per world (no plan needed)."""
    share = 0.3 if world == "alpha" else 0.7
    return {name: low + share * (high - low)
            for name, (low, high) in card["feature_ranges"].items()}


@pytest.fixture(scope="module")
def page(campaign_dir, model_dir):
    from .conftest import Page

    return Page(build_report(campaign_dir, model_dir, feature_fn=mid_range_features))


def fmt(value: float, component: str) -> str:
    if component.startswith("trans"):
        return f"{value:.4f}"
    return f"{value:.5f} ({math.degrees(value):.3f}°)"


def test_predictions_next_to_measured(page, model_dir):
    store = ModelStore(model_dir)
    table = page.table(["world", "runs", "component"])
    rows = {(r[0], r[2]): dict(zip(table["header"], r, strict=False)) for r in table["rows"]}
    assert len(rows) == 6  # 2 worlds x 3 components: rot_std has no model (R² ≤ 0)
    assert any("rot_std: not predicted, no model of" in n for n in page.notes)
    for world, errors in ERRORS.items():
        expected = predict_features(mid_range_features(world, store.card), store)
        measured = {"trans_mean": np.mean([t for t, _ in errors]),
                    "trans_std": np.std([t for t, _ in errors]),
                    "rot_mean": np.mean([r for _, r in errors]),
                    "rot_std": np.std([r for _, r in errors])}
        for component, value in measured.items():
            if expected[component]["status"] == "no_model":  # thesis-realistic rot_std
                assert (world, component) not in rows
                continue
            row = rows[(world, component)]
            assert row["runs"] == str(len(errors))
            assert row["measured (mean over runs)"] == fmt(value, component)
            assert expected[component]["status"] == "ok"
            assert row["predicted"] == fmt(expected[component]["value"], component)
            assert row["interval"] == (f"{fmt(expected[component]['low'], component)} – "
                                       f"{fmt(expected[component]['high'], component)}")
            inside = expected[component]["low"] <= value <= expected[component]["high"]
            assert row["measured inside"] == ("yes" if inside else "no")


def test_card_metrics_and_regression_plot(page, model_dir):
    card = json.loads((model_dir / "card.json").read_text())
    table = page.table(["component", "unit", "model"])
    rows = {(r[0], r[2]): dict(zip(table["header"], r, strict=False)) for r in table["rows"]}
    for component, comp in card["components"].items():
        best = comp["best"]
        metrics = comp["models"][best]["metrics"]
        row = rows[(component, best)]
        assert row["R² mean"] == f"{metrics['r2_mean']:.3f}"
        assert row["LOO coverage"] == f"{metrics['leave_one_out']['coverage']:.3f}"
    assert f"Model {MODEL}" in page.headings
    assert any(img["alt"] == f"predicted vs measured, model {MODEL}" for img in page.images)
    assert any("SLAM configuration 'thesis-gmapping'" in n for n in page.notes)


def test_damaged_and_unfound_models_are_notes(campaign_dir, model_dir, tmp_path, parse):
    models = tmp_path / "models"
    shutil.copytree(model_dir, models / "good")
    shutil.copytree(model_dir, models / "damaged")
    shutil.copytree(model_dir, models / "old_features")
    joblib_file = next((models / "damaged").glob("*.joblib"))
    joblib_file.write_bytes(joblib_file.read_bytes()[:-10])
    card = json.loads((models / "old_features" / "card.json").read_text())
    card["feature_version"] = "0+old"
    (models / "old_features" / "card.json").write_text(json.dumps(card))
    page = parse(build_report(campaign_dir, models))          # real features: worlds unknown
    assert page.headings.count(f"Model {MODEL}") == 3
    assert any("model not usable for predictions" in n and "checksum" in n for n in page.notes)
    assert any("model not usable for predictions" in n and "feature version 0+old" in n
               for n in page.notes)
    assert any(n.startswith("alpha: no prediction (world file alpha.world not found")
               and "report --worlds DIR" in n for n in page.notes)
    assert not any(t["header"][:3] == ["world", "runs", "component"] for t in page.tables)


def test_campaign_of_summary_csv_only(campaign_dir, model_dir, tmp_path, parse):
    data = tmp_path / "csv_only"
    data.mkdir()
    lines = (campaign_dir / "summary.csv").read_text().splitlines()
    header = lines[0].split(",")
    beta = lines[2].split(",")
    beta[header.index("trans_std")] = ""                   # a hole in the table
    (data / "summary.csv").write_text("\n".join([lines[0], lines[1], ",".join(beta)]) + "\n")
    page = parse(build_report(data, model_dir, feature_fn=mid_range_features))
    table = page.table(["world", "runs", "component"])
    rows = {(r[0], r[2]): dict(zip(table["header"], r, strict=False)) for r in table["rows"]}
    assert rows[("alpha", "trans_mean")]["measured (mean over runs)"] == "0.2000"
    assert rows[("beta", "trans_std")]["measured (mean over runs)"] == "—"
    assert rows[("beta", "trans_std")]["measured inside"] == "—"
    assert any(img["alt"].startswith("predicted vs measured") for img in page.images)


def test_models_argument_errors(campaign_dir, tmp_path):
    with pytest.raises(InputError, match="models folder not found"):
        build_report(campaign_dir, tmp_path / "nope")
    (tmp_path / "empty").mkdir()
    with pytest.raises(InputError, match="no model folder"):
        build_report(campaign_dir, tmp_path / "empty")


def test_world_file_resolution(campaign_dir, tmp_path):
    data = tmp_path / "c" / "data"
    shutil.copytree(campaign_dir, data)
    campaign = load_campaign(data)
    assert find_world_file(campaign, "alpha") is None       # worlds/alpha.world nowhere
    (tmp_path / "c" / "worlds").mkdir()
    (tmp_path / "c" / "worlds" / "alpha.world").write_text("")  # relative to DATA's parent
    assert find_world_file(load_campaign(data), "alpha") == tmp_path / "c" / "worlds" / \
        "alpha.world"
    campaign.worlds["tiny"] = campaign.worlds.pop("beta")
    assert find_world_file(campaign, "tiny") == SHIPPED_WORLDS / "tiny.world"


def test_a_best_model_with_r2_at_most_0_is_not_bold():
    """own-realistic's rot_mean best (LOO R² −0.16) was bolded; the positive one stays bold."""
    from slam_predict.report.models import metrics_table

    def model(r2_mean, loo_r2):
        return {"features_used": ["a"], "metrics": {"r2_mean": r2_mean,
                                                     "leave_one_out": {"r2": loo_r2}}}

    card = {"components": {
        "trans_mean": {"best": "single:a", "models": {"single:a": model(0.31, 0.83)}},
        "rot_mean": {"best": "single:b", "models": {"single:b": model(0.2, -0.16)}},
        "rot_std": {"best": "single:c", "models": {"single:c": model(-0.06, 0.11)}}}}
    rows = [r for r in metrics_table(card).splitlines() if r.startswith("<tr")]
    bold = [r for r in rows if 'class="best"' in r]
    assert len(rows) == 3 and len(bold) == 1 and "single:a" in bold[0]


def test_tables_scroll_instead_of_being_cut():
    """The 14-column model table was cut off at the page's right edge."""
    from slam_predict.report import html as H

    assert H.table(["a"], [[1]]).startswith('<div class="table"><table>')
    assert "div.table{overflow-x:auto;max-width:100%" in H.STYLE


def test_a_model_of_another_slam_algorithm_is_not_scored(campaign_dir, model_dir, tmp_path):
    """A Karto campaign and a GMapping model: the card is shown, its predictions are not set
    beside the Karto measurements, and the map captions name Karto."""
    from .conftest import Page
    from .fake_campaign import copy

    data = copy(campaign_dir, tmp_path / "karto")
    for path in data.glob("*/run_*/run.json"):
        record = json.loads(path.read_text())
        record["slam"] = {"type": "karto", "params_hash": "k"}
        path.write_text(json.dumps(record))
    raw = build_report(data, model_dir, feature_fn=mid_range_features)
    page, text = Page(raw), html.unescape(raw)
    assert f"{MODEL} predicts the errors of GMapping; this campaign's runs used Karto: its " \
           "predictions are not compared with them." in text
    assert not any(h.startswith(f"Predictions of {MODEL}") for h in page.headings)
    assert any(h.startswith(f"Model {MODEL}") for h in page.headings)
    assert "final Karto map" in text and "final GMapping map" not in text


def test_card_overviews_name_the_fitted_collection_settings():
    """Both card overviews (plan-only and robot-aware) show the training chain's fitted
    settings, or say none was declared."""
    from slam_predict.report.models import card_overview
    from slam_predict.report.robot_models import overview

    fitted = {"sources": {"fitted": {"slam_compute.rebuild_s_per_line_cell": "4x, fitted"}}}
    for render in (card_overview, overview):
        shown = render(fitted)
        assert "fitted collection settings" in shown
        assert "slam_compute.rebuild_s_per_line_cell: 4x, fitted" in shown
        assert "none declared" in render({})
