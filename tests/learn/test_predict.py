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
        assert entry["unit"] == unit
        assert 0 <= entry["low"] <= entry["value"] <= entry["high"]
        assert entry["model"].startswith("tiny-realistic/")
    assert result["trans_mean"]["value"] == pytest.approx(0.9, abs=0.1)  # 1e-3·800 + 0.1
    assert result["warnings"] == []
    assert result["confidence"] == 0.9 and result["setting"] == "realistic"


def test_one_component_only(store):
    result = predict_features({"length": 800.0, "noise": 0.0}, store, "rot_mean")
    assert "rot_mean" in result and "trans_mean" not in result


def test_out_of_range_features_warn_and_negative_values_clip(store):
    result = predict_features({"length": -5000.0, "noise": 0.0}, store, "trans_mean")
    assert result["trans_mean"]["value"] == 0.0 and result["trans_mean"]["low"] == 0.0
    text = " ".join(result["warnings"])
    assert "features outside the training range: length = -5000 not in [" in text
    assert "clipped to 0" in text


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
