"""The model card: ``models/<name>/card.json``, the one schema of both model families.

Every card has the :data:`REQUIRED` keys: ``format`` (:data:`FORMAT`), ``name``, ``setting``
(realistic/optimistic for a plan-only card, ``robots`` for a robot-aware one),
``feature_version`` and ``features`` (the plan feature columns), ``components`` (per error
component: ``unit``, ``best`` model id, ``models`` {id: {``metrics``, ``plain``…}}),
``versions`` (library versions), ``files`` (name → SHA-256) and ``training_buildings``.
Optional: ``kind`` (:data:`PLAN_KIND`, the default, or :data:`ROBOT_KIND`), ``slam`` (the SLAM
algorithm of the training runs, :data:`SLAM_ALGORITHMS`; :data:`DEFAULT_SLAM` when absent, as in
cards written before it was recorded), ``description``,
``created``, ``priority``, ``feature_config``, ``confidence`` (interval level, 0.9 if absent),
``sources``.

Plan-only cards (:mod:`~slam_predict.learn.train`) add ``feature_ranges``, ``runs``,
``slam_config_hash`` and ``learning_config``; each model entry has ``features_used`` and
``chosen``. Robot-aware cards (:mod:`~slam_predict.learn.robot.train`) add the
:data:`ROBOT_REQUIRED` keys ``max_urange_m`` (GMapping's maxUrange, m, or null),
``input_ranges`` (input → [low, high]) and ``design`` (the training configurations), plus
``robot_inputs``, ``robot_units``, ``derived_inputs``, ``sightline``/``sightline_curves``,
``odom_model``, ``interval_runs`` (runs the std intervals describe), ``exploration``,
``robot_learning_config``; their model metrics are per evaluation protocol
(:data:`PROTOCOLS`). A card's kind is read and checked here only (:func:`kind_of`,
:func:`check_kind`).
"""
from __future__ import annotations

import json
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from slam_predict.errors import InputError, did_you_mean

FORMAT = 1
CARD = "card.json"
REQUIRED = ("format", "name", "setting", "feature_version", "features", "components",
            "versions", "files", "training_buildings")
PLAN_KIND = "plan"          # plan features → the four components
ROBOT_KIND = "robots"       # plan features + the robot's laser and odometry → the components
ROBOT_REQUIRED = ("max_urange_m", "input_ranges", "design")
PROTOCOLS = ("buildings", "configs", "both")   # robot-aware evaluation: what is held out
POINTS_FILE = "training_points.csv"   # a robot-aware folder's training POINT rows
DEFAULT_ROBOT_MODEL = "own-robots"
ROBOT_TRAIN_HINT = ("train one with 'slam-predict learn train --runs DATA_DIR... --features "
                    "CSV --design data/campaigns/robots/design.yaml --name own-robots' "
                    "(docs/learning.md)")


def kind_of(card: Mapping[str, Any] | None) -> str:
    """The card's kind: :data:`PLAN_KIND` when it names none."""
    return str((card or {}).get("kind", PLAN_KIND))


def is_robot_card(card: Mapping[str, Any] | None) -> bool:
    """True for the card of a robot-aware model folder."""
    return bool(card) and kind_of(card) == ROBOT_KIND


def check_kind(card: Mapping[str, Any], expected: str, card_path: Path) -> None:
    """InputError (one line, naming what to use instead) unless the card is of ``expected``
    kind; a robot-aware card must also hold the :data:`ROBOT_REQUIRED` keys."""
    kind = kind_of(card)
    if expected == PLAN_KIND and kind != PLAN_KIND:
        raise InputError(f"model '{card['name']}' is a robot-aware model (kind {kind}): it "
                         "needs robot inputs; load it with slam_predict.learn.load_model",
                         card_path)
    if expected == ROBOT_KIND and kind != ROBOT_KIND:
        raise InputError(f"model {card_path.parent.name} is a plan-only model (kind {kind}): "
                         f"--robot needs a robot-aware one (kind {ROBOT_KIND}), default "
                         f"{DEFAULT_ROBOT_MODEL}; {ROBOT_TRAIN_HINT}", card_path)
    if expected == ROBOT_KIND:
        for key in ROBOT_REQUIRED:
            if key not in card:
                raise InputError(f"corrupt model card (missing '{key}'); retrain with "
                                 "'slam-predict learn robots'", card_path)


def read_card(path: os.PathLike | str) -> dict[str, Any]:
    """The validated card of a model folder (any kind)."""
    folder = Path(path)
    card_path = folder / CARD
    if not folder.is_dir():
        raise InputError("model folder not found", folder)
    if not card_path.is_file():
        raise InputError("not a model folder (no card.json)", folder)
    try:
        card = json.loads(card_path.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputError(f"corrupt model card ({exc.__class__.__name__}: {exc})",
                         card_path) from None
    if not isinstance(card, dict):
        raise InputError("corrupt model card (not a JSON object)", card_path)
    missing = [k for k in REQUIRED if k not in card]
    if missing:
        raise InputError(f"corrupt model card (missing '{missing[0]}')", card_path)
    if card["format"] != FORMAT:
        raise InputError(f"model format {card['format']} is not supported (this slam_predict "
                         f"reads format {FORMAT}); retrain with 'slam-predict learn train'",
                         card_path)
    return card


def input_names(card: Mapping[str, Any]) -> list[str]:
    """The model's input columns: plan features, then (robot-aware) derived and robot
    inputs."""
    if not is_robot_card(card):
        return list(card["features"])
    from slam_predict.learn.robot.inputs import ROBOT_INPUTS

    return (list(card["features"]) + list(card.get("derived_inputs") or [])
            + list(card.get("robot_inputs") or ROBOT_INPUTS))


def confidence(card: Mapping[str, Any]) -> float:
    """The card's interval confidence (0.9 when absent)."""
    return card.get("confidence", 0.9)


SLAM_ALGORITHMS = ("gmapping", "karto")   # the SLAM algorithms a dataset row or card may name
DEFAULT_SLAM = "gmapping"   # the algorithm of a row or card that names none


SLAM_LABELS = {"gmapping": "GMapping", "karto": "Karto"}   # as the back-ends' ``label``
RANGE_CAP_NAMES = {"gmapping": "GMapping's maxUrange", "karto": "Karto's max_laser_range"}


def training_fitted_settings(card: Mapping[str, Any]) -> dict[str, str]:
    """The collection settings the model's training runs used that were fitted to the seed
    study, not measured (``sources.fitted``: setting → how it was fitted; {} when none)."""
    return dict((card.get("sources") or {}).get("fitted") or {})


def fitted_summary(card: Mapping[str, Any]) -> str:
    """The card's fitted collection settings on one line ("none declared" without any)."""
    fitted = training_fitted_settings(card)
    return "; ".join(f"{key}: {how}" for key, how in fitted.items()) or "none declared"


def slam_label(name: str | None) -> str:
    """The human-readable name of a SLAM algorithm (GMapping when None)."""
    return SLAM_LABELS.get(name or DEFAULT_SLAM, name or "")


def range_cap_name(slam: str) -> str:
    """What caps the laser range the SLAM algorithm uses (card field ``max_urange_m``)."""
    return RANGE_CAP_NAMES.get(slam, f"{slam}'s range cap")


def card_slam(card: Mapping[str, Any]) -> str:
    """The SLAM algorithm whose runs the card's models were trained on (:data:`DEFAULT_SLAM`
    when it names none)."""
    return str(card.get("slam", DEFAULT_SLAM))


def check_slam(slam: str | None, card: Mapping[str, Any] | None = None,
               card_path: os.PathLike | str | None = None) -> None:
    """InputError unless ``slam`` is None or a SLAM algorithm of :data:`SLAM_ALGORITHMS` and,
    with a ``card`` (read from ``card_path``, named in the message), the one its models were
    trained on."""
    if slam is None:
        return
    if slam not in SLAM_ALGORITHMS:
        raise InputError(f"unknown SLAM algorithm '{slam}' (the models know "
                         f"{', '.join(SLAM_ALGORITHMS)})" + did_you_mean(slam, SLAM_ALGORITHMS))
    if card is not None and slam != card_slam(card):
        raise InputError(f"model {card.get('name')} was trained on {card_slam(card)} runs, not "
                         f"{slam}: name a model trained for {slam}", card_path)
