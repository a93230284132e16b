"""Model store: round trip, card contents, and one-line refusals of bad model folders."""
from __future__ import annotations

import json
import shutil

import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.learn.model import resolve_store
from slam_predict.learn.store import CARD, ModelStore, list_stores

from .conftest import synthetic_dataset


def copy(tiny_models, tmp_path, name="m"):
    target = tmp_path / name
    shutil.copytree(tiny_models / "tiny-realistic", target)
    return target


def edit_card(folder, **changes):
    card = json.loads((folder / CARD).read_text())
    card.update(changes)
    (folder / CARD).write_text(json.dumps(card))


def test_card_says_what_the_models_were_trained_on(tiny_models):
    card = json.loads((tiny_models / "tiny-realistic" / CARD).read_text())
    assert card["setting"] == "realistic" and card["slam_config_hash"] == "abc123"
    assert card["feature_version"] == "test-v1" and card["features"] == ["length", "noise"]
    assert len(card["training_buildings"]) == 30 and card["runs"]["w00"] == 5
    assert card["feature_config"] == {"some": "config"}
    assert set(card["components"]) == {"trans_mean", "trans_std", "rot_mean", "rot_std"}
    entry = card["components"]["trans_mean"]
    best = entry["models"][entry["best"]]
    assert "length" in best["features_used"]
    assert best["metrics"]["r2_mean"] > 0.8 and "coverage" in best["metrics"]["leave_one_out"]
    assert card["versions"]["scikit-learn"] and set(card["files"]) == {
        f"{c}.{ext}" for c in card["components"] for ext in ("joblib", "plain.json")}


def test_round_trip_predictions(tiny_models):
    store = ModelStore(tiny_models / "tiny-realistic", "test-v1")
    data = synthetic_dataset()
    model = store.estimator("trans_mean")
    pred = model.predict(data.X)
    assert np.corrcoef(pred, data.target("trans_mean"))[0, 1] > 0.95
    low, high = model.predict_interval(data.X).T
    assert np.all(low <= pred) and np.all(pred <= high)


def test_truncated_model_file_is_refused(tiny_models, tmp_path):
    folder = copy(tiny_models, tmp_path)
    data = (folder / "trans_mean.joblib").read_bytes()
    (folder / "trans_mean.joblib").write_bytes(data[: len(data) // 2])
    with pytest.raises(InputError, match="corrupt model file") as err:
        ModelStore(folder, "test-v1")  # checked on opening, whichever file is damaged
    assert "trans_mean.joblib" in err.value.one_line()


def test_garbage_with_matching_checksum_is_refused(tiny_models, tmp_path):
    folder = copy(tiny_models, tmp_path)
    (folder / "rot_std.joblib").write_bytes(b"not a pickle")
    from slam_predict.learn.store import sha256

    card = json.loads((folder / CARD).read_text())
    card["files"]["rot_std.joblib"] = sha256(folder / "rot_std.joblib")
    (folder / CARD).write_text(json.dumps(card))
    with pytest.raises(InputError, match=r"corrupt model file \("):
        ModelStore(folder, "test-v1").estimator("rot_std")


@pytest.mark.parametrize("content,message", [("{not json", "corrupt model card"),
                                             ("[1, 2]", "not a JSON object"),
                                             ('{"format": 1}', "missing 'name'")])
def test_corrupt_card_is_refused(tiny_models, tmp_path, content, message):
    folder = copy(tiny_models, tmp_path)
    (folder / CARD).write_text(content)
    with pytest.raises(InputError, match=message):
        ModelStore(folder)


def test_incompatible_versions_are_refused(tiny_models, tmp_path):
    folder = copy(tiny_models, tmp_path)
    with pytest.raises(InputError, match="feature version test-v1, this slam_predict computes v9"):
        ModelStore(folder, "v9")
    card = json.loads((folder / CARD).read_text())
    edit_card(folder, versions={**card["versions"], "scikit-learn": "0.24.2"})
    with pytest.raises(InputError, match="different major version"):
        ModelStore(folder, "test-v1")
    edit_card(folder, versions={**card["versions"], "scikit-learn": "1.0.0"}, format=1)
    assert "scikit-learn 1.0.0" in ModelStore(folder, "test-v1").notes[0]
    edit_card(folder, format=99)
    with pytest.raises(InputError, match="format 99"):
        ModelStore(folder)


def test_resolve_by_name_best_and_setting(tiny_models, tmp_path):
    models = tmp_path / "models"
    low = copy(tiny_models, models, "a-low")
    high = copy(tiny_models, models, "b-high")
    other = copy(tiny_models, models, "c-opt")
    edit_card(high, priority=5)
    edit_card(other, setting="optimistic", priority=10)
    assert [p.name for p in list_stores(models)] == ["a-low", "b-high", "c-opt"]
    assert resolve_store(models, "best", "realistic", None).path == high
    assert resolve_store(models, "best", "optimistic", None).path == other
    assert resolve_store(models, "a-low", "realistic", None).path == low
    with pytest.raises(InputError, match="did you mean 'a-low'"):
        resolve_store(models, "a-lo", "realistic", None)
    with pytest.raises(InputError, match="trained for the optimistic setting"):
        resolve_store(models, "c-opt", "realistic", None)
    with pytest.raises(InputError, match="no model of gmapping's error for the fancy setting"):
        resolve_store(models, "best", "fancy", None)


def test_corrupt_plain_file_is_refused(tiny_models, tmp_path):
    from slam_predict.learn.store import sha256

    folder = copy(tiny_models, tmp_path)
    (folder / "rot_mean.plain.json").write_text("{}")
    with pytest.raises(InputError, match="rot_mean.plain.json: corrupt model file"):
        ModelStore(folder, "test-v1")
    card = json.loads((folder / CARD).read_text())  # consistent checksum, wrong content
    card["files"]["rot_mean.plain.json"] = sha256(folder / "rot_mean.plain.json")
    (folder / CARD).write_text(json.dumps(card))
    store = ModelStore(folder, "test-v1")
    with pytest.raises(InputError, match="rot_mean.plain.json: corrupt model file"):
        store.plain("rot_mean", store.best("rot_mean"))


def test_a_dataset_no_model_can_learn_is_not_stored(tmp_path):
    """Targets of pure noise: every mean test R² ≤ 0, so no component has a best model."""
    import dataclasses

    import numpy as np

    from slam_predict.learn.results import run_evaluation
    from slam_predict.learn.train import train_store

    from .conftest import tiny_config

    data = synthetic_dataset()
    noise = dataclasses.replace(data, Y=np.random.default_rng(1).normal(1.0, 0.1, data.Y.shape))
    outcome = run_evaluation(noise, tiny_config())
    assert outcome.best == {}
    with pytest.raises(InputError, match="no model predicts any component better"):
        train_store(noise, tiny_config(), outcome, "noise", tmp_path)
    assert not (tmp_path / "noise").exists()
