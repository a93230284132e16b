"""learn/slam_choice.py: the model of a SLAM algorithm is the one whose card says it was trained
for it, searched in --models-dir, or in $SLAM_PREDICT_MODELS and then the package's models/."""
from __future__ import annotations

import json
import shutil

import pytest

from slam_predict.errors import InputError
from slam_predict.learn import slam_choice
from slam_predict.learn.card import PLAN_KIND, ROBOT_KIND, card_slam
from slam_predict.learn.model import resolve_store
from slam_predict.learn.slam_choice import find_model, search_dirs


def copy(source, folder, name, **card_changes):
    target = folder / name
    shutil.copytree(source / "tiny-realistic", target)
    path = target / "card.json"
    path.write_text(json.dumps({**json.loads(path.read_text()), "name": name, **card_changes}))
    return target


def test_a_card_without_slam_was_trained_for_gmapping():
    assert card_slam({}) == "gmapping"
    assert card_slam({"slam": "karto"}) == "karto"


def test_best_model_per_algorithm(tiny_models, tmp_path):
    models = tmp_path / "models"
    gmapping = copy(tiny_models, models, "a-gmapping")
    karto = copy(tiny_models, models, "b-karto", slam="karto", priority=9)
    copy(tiny_models, models, "c-karto", slam="karto", priority=1)
    assert find_model("gmapping", PLAN_KIND, models_dir=models) == gmapping
    assert find_model("karto", PLAN_KIND, models_dir=models) == karto
    assert resolve_store(models, "best", "realistic", None).path == gmapping
    assert resolve_store(models, "best", "realistic", None, "karto").path == karto
    with pytest.raises(InputError, match="no robot-aware model of karto's error.*collect_karto"):
        find_model("karto", ROBOT_KIND, models_dir=models)
    with pytest.raises(InputError, match="b-karto was trained on karto runs, not gmapping"):
        find_model("gmapping", PLAN_KIND, "b-karto", models)
    with pytest.raises(InputError, match="did you mean 'b-karto'"):
        find_model("karto", PLAN_KIND, "b-kart", models)


def test_environment_folder_first_then_the_shipped_models(tiny_models, tmp_path, monkeypatch):
    shipped, own = tmp_path / "shipped", tmp_path / "own"
    shipped_gmapping = copy(tiny_models, shipped, "thesis")
    own_karto = copy(tiny_models, own, "my-karto", slam="karto")
    monkeypatch.setattr(slam_choice, "SHIPPED_MODELS", shipped)
    monkeypatch.delenv("SLAM_PREDICT_MODELS", raising=False)
    assert search_dirs() == [shipped]
    with pytest.raises(InputError, match=f"no model of karto's error in {shipped}") as caught:
        find_model("karto", PLAN_KIND)
    assert "the package ships none for karto: docs/karto.md" in str(caught.value)
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(InputError) as caught:
        find_model("karto", PLAN_KIND, models_dir=empty)
    assert "ships none" not in str(caught.value)       # the user's own folder alone
    monkeypatch.setenv("SLAM_PREDICT_MODELS", str(own))
    assert search_dirs() == [own, shipped]
    assert search_dirs(tmp_path) == [tmp_path]
    assert find_model("karto", PLAN_KIND) == own_karto
    assert find_model("gmapping", PLAN_KIND) == shipped_gmapping     # none in own/
    own_gmapping = copy(tiny_models, own, "my-gmapping")
    assert find_model("gmapping", PLAN_KIND) == own_gmapping         # own/ first
    assert find_model("gmapping", PLAN_KIND, "thesis") == shipped_gmapping
