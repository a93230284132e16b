"""The model card schema: kinds, the one kind check, input columns, reading a card."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from slam_predict.errors import InputError
from slam_predict.learn.card import (
    CARD,
    PLAN_KIND,
    ROBOT_KIND,
    ROBOT_REQUIRED,
    check_kind,
    input_names,
    is_robot_card,
    kind_of,
    read_card,
)
from slam_predict.learn.robot.inputs import ROBOT_INPUTS

MODELS = Path(__file__).resolve().parents[2] / "models"


def robot_card(**extra) -> dict:
    card = {"name": "r", "kind": ROBOT_KIND, "features": ["building_area"],
            "derived_inputs": ["laser_blind_fraction"]}
    card.update({key: {} for key in ROBOT_REQUIRED})
    return {**card, **extra}


def test_kind_defaults_to_plan_and_robot_cards_are_recognised():
    assert kind_of({"name": "p"}) == PLAN_KIND and kind_of(None) == PLAN_KIND
    assert is_robot_card(robot_card()) and not is_robot_card({"kind": PLAN_KIND})
    assert not is_robot_card(None) and not is_robot_card({})


def test_check_kind_names_the_other_family(tmp_path):
    path = tmp_path / "own-robots" / CARD
    check_kind(robot_card(), ROBOT_KIND, path)
    check_kind({"name": "p"}, PLAN_KIND, path)
    with pytest.raises(InputError, match="is a robot-aware model.*load_model"):
        check_kind(robot_card(), PLAN_KIND, path)
    with pytest.raises(InputError, match="own-robots is a plan-only model.*learn train --runs"):
        check_kind({"name": "p"}, ROBOT_KIND, path)
    for key in ROBOT_REQUIRED:
        card = robot_card()
        del card[key]
        with pytest.raises(InputError, match=f"missing '{key}'"):
            check_kind(card, ROBOT_KIND, path)


def test_input_names_plan_then_derived_then_robot():
    assert input_names({"features": ["a", "b"]}) == ["a", "b"]
    assert input_names(robot_card()) == ["building_area", "laser_blind_fraction",
                                          *ROBOT_INPUTS]


def test_every_shipped_card_reads_with_its_kind():
    folders = sorted(p for p in MODELS.iterdir() if (p / CARD).is_file())
    assert folders, "no shipped model folder"
    for folder in folders:
        card = read_card(folder)
        expected = ROBOT_KIND if folder.name == "own-robots" else PLAN_KIND
        assert kind_of(card) == expected
        check_kind(card, expected, folder / CARD)


def test_read_card_refuses_a_bad_card(tmp_path):
    with pytest.raises(InputError, match="model folder not found"):
        read_card(tmp_path / "nope")
    with pytest.raises(InputError, match="no card.json"):
        read_card(tmp_path)
    (tmp_path / CARD).write_text("[1]")
    with pytest.raises(InputError, match="not a JSON object"):
        read_card(tmp_path)
    (tmp_path / CARD).write_text(json.dumps({"format": 1}))
    with pytest.raises(InputError, match="missing 'name'"):
        read_card(tmp_path)
