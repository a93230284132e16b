"""Prediction from a feature vector: components, intervals, clipping and range warnings."""
from __future__ import annotations

import pytest

from slam_predict.errors import InputError
from slam_predict.learn.predict import components_of, predict_features
from slam_predict.learn.store import ModelStore


@pytest.fixture()
def store(tiny_models):
    return ModelStore(tiny_models / "tiny-realistic", "test-v1")


def test_all_components_with_intervals_and_models(store):
    result = predict_features({"length": 800.0, "noise": 0.0}, store)
    for comp, unit in (("trans_mean", "m"), ("trans_std", "m"), ("rot_mean", "rad"),
                       ("rot_std", "rad")):
        entry = result[comp]
        assert entry["unit"] == unit and entry["status"] == "ok"
        assert 0 <= entry["low"] <= entry["value"] <= entry["high"]
        assert entry["model"].startswith("tiny-realistic/")
    assert result["trans_mean"]["value"] == pytest.approx(0.9, abs=0.1)  # 1e-3·800 + 0.1
    assert result["warnings"] == []
    assert result["confidence"] == 0.9 and result["setting"] == "realistic"


def test_one_component_only(store):
    result = predict_features({"length": 800.0, "noise": 0.0}, store, "rot_mean")
    assert "rot_mean" in result and "trans_mean" not in result


def test_out_of_range_features_warn_and_negative_values_are_below_range(store):
    """A negative model output is not reported as 0 (the old clipping gave value 0 and the
    zero-width interval 0–0): it is 'below the model's range', with the raw output kept."""
    result = predict_features({"length": -5000.0, "noise": 0.0}, store, "trans_mean")
    entry = result["trans_mean"]
    assert entry["status"] == "below_range"
    assert entry["value"] is None and entry["low"] is None
    assert entry["raw_value"] == pytest.approx(1e-3 * -5000 + 0.1, abs=0.3)
    assert entry["high"] is None or entry["high"] > 0
    text = " ".join(result["warnings"])
    assert "features outside the training range: length = -5000 not in [" in text
    assert "trans_mean: the model's output -4." in text and "below the model's range" in text


def check_entry(entry, value, low, high):
    """The reported entry is inside its own non-zero-width interval, or has no value."""
    if entry["status"] == "ok":
        assert entry["value"] == value > 0
        if entry["low"] is not None:
            assert 0 <= entry["low"] <= entry["value"] <= entry["high"]
            assert entry["high"] > entry["low"]
            assert entry["high"] == max(high, value)
            assert entry["low"] == max(min(low, value), 0.0)
    else:
        assert entry["status"] == "below_range" and value <= 0
        assert entry["value"] is None and entry["low"] is None
        assert entry["high"] is None or entry["high"] == max(high, value) > 0


@pytest.mark.parametrize("value, low, high", [
    (0.592, 0.162, 0.562),     # the noise image: value above its own interval
    (0.10, 0.15, 0.30),        # value below its interval
    (-0.8852, -1.2, -0.3),     # the two-room plan: all negative, clipping gave 0–0
    (-0.2, -0.5, 0.17),        # negative value, interval reaching above 0
    (0.0, 0.0, 0.0),           # exactly 0
    (0.05, -0.1, 0.2),         # ordinary, low clipped at 0
    (0.3, 0.3, 0.3),           # zero-width interval around a positive value
])
def test_value_never_outside_its_interval_nor_zero_width(value, low, high):
    from slam_predict.learn.predict import component_entry

    check_entry(component_entry(value, low, high, "m", "s/m"), value, low, high)


def test_random_outputs_respect_the_interval_rules():
    import numpy as np

    from slam_predict.learn.predict import component_entry

    rng = np.random.default_rng(3)
    for value, a, b in rng.normal(size=(500, 3)):
        check_entry(component_entry(value, min(a, b), max(a, b), "m", "s/m"), value,
                    min(a, b), max(a, b))


def test_a_component_whose_best_model_has_r2_at_most_0_is_not_offered(tiny_models, tmp_path):
    import json
    import shutil

    from slam_predict.learn.store import CARD

    folder = tmp_path / "m"
    shutil.copytree(tiny_models / "tiny-realistic", folder)
    card = json.loads((folder / CARD).read_text())
    comp = card["components"]["rot_std"]
    comp["models"][comp["best"]]["metrics"]["leave_one_out"]["r2"] = -0.16
    (folder / CARD).write_text(json.dumps(card))
    changed = ModelStore(folder, "test-v1")
    result = predict_features({"length": 800.0, "noise": 0.0}, changed)
    assert result["rot_std"]["status"] == "no_model" and result["rot_std"]["value"] is None
    assert result["rot_std"]["r2"] == -0.16
    assert any("rot_std: no model" in w and "-0.16" in w for w in result["warnings"])
    assert result["trans_mean"]["status"] == "ok"


def test_missing_or_unknown_inputs(store):
    with pytest.raises(InputError, match="feature 'noise' needed by model tiny-realistic"):
        predict_features({"length": 1.0}, store)
    with pytest.raises(InputError, match="feature 'length' could not be computed"):
        predict_features({"length": float("nan"), "noise": 0.0}, store, "trans_mean")
    with pytest.raises(InputError, match="did you mean 'rot_std'"):
        components_of("rot_sdt")
    assert components_of("all") == ("trans_mean", "trans_std", "rot_mean", "rot_std")


def test_range_warning_is_one_line_and_truncated():
    from slam_predict.learn.predict import range_warning

    features = {f"f{i}": 10.0 for i in range(9)}
    ranges = {f"f{i}": [0.0, 1.0] for i in range(9)}
    note = range_warning(features, list(features), ranges, shown=6)
    assert note.count(" not in [") == 6 and note.endswith("(and 3 more)")
    assert range_warning({"a": 0.5}, ["a"], {"a": [0.0, 1.0]}) is None


def test_linear_fast_path_equals_the_pickled_models(store):
    import numpy as np

    from slam_predict.learn.predict import _evaluate

    x = np.array([[700.0, 0.3]])
    for comp in ("trans_mean", "trans_std", "rot_mean", "rot_std"):
        model_id = store.best(comp)
        entry = store.card["components"][comp]["models"][model_id]
        assert entry["plain"]  # single lines and elasticnet are linear
        fast = _evaluate(store, comp, model_id, x)
        est = store.estimator(comp, model_id)
        slow = (est.predict(x)[0], *est.predict_interval(x)[0])
        np.testing.assert_allclose(fast, slow, rtol=1e-10)
