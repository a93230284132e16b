"""Which model folder predicts a SLAM algorithm's error: the card's ``slam`` field.

A model predicts the error of the SLAM algorithm whose runs it was trained on; its card names
that algorithm (:func:`~slam_predict.learn.card.card_slam`; a card without the field was
trained on GMapping runs, as every model was before there was another back-end).
:func:`find_model` picks the folder for an algorithm, a card kind (plan-only or robot-aware)
and, for plan-only cards, the seed study's robot setting. It searches ``--models-dir`` alone
when given, else ``$SLAM_PREDICT_MODELS`` first and then the package's ``models/``
(:func:`search_dirs`): a user's own Karto model beside the shipped GMapping ones.
"""
from __future__ import annotations

import logging
import os
from collections.abc import Sequence
from pathlib import Path

from slam_predict.errors import InputError, did_you_mean
from slam_predict.learn.card import (  # noqa: F401  (DEFAULT_SLAM re-exported)
    CARD,
    DEFAULT_ROBOT_MODEL,
    DEFAULT_SLAM,
    PLAN_KIND,
    ROBOT_KIND,
    card_slam,
    check_slam,
    kind_of,
    read_card,
)
from slam_predict.learn.store import MODELS_ENV, SHIPPED_MODELS, list_stores

LOG = logging.getLogger(__name__)
TRAIN_HINTS = {
    PLAN_KIND: "slam-predict learn dataset on the campaign, then learn train DATASET --slam {}",
    ROBOT_KIND: "slam-predict learn train --runs DATA --design DESIGN --slam {}",
}


def search_dirs(models_dir: os.PathLike | str | None = None) -> list[Path]:
    """The model folders' parents searched, in order: ``models_dir`` alone when given, else
    ``$SLAM_PREDICT_MODELS`` (when set) and the package's ``models/``."""
    if models_dir is not None:
        return [Path(models_dir)]
    env = os.environ.get(MODELS_ENV)
    dirs = [Path(env)] if env else []
    return dirs + [SHIPPED_MODELS] if SHIPPED_MODELS not in dirs else dirs


def train_hint(slam: str, kind: str = PLAN_KIND) -> str:
    """How to make a model of ``slam``'s error (one clause, for error messages)."""
    settings = " --settings config/collect_karto.yaml" if slam == "karto" else ""
    return (f"to make one, collect {slam} runs (slam-predict collect WORLDS --slam {slam}"
            f"{settings} --out DATA) and train on them ({TRAIN_HINTS[kind].format(slam)}; "
            "docs/howto/choose-slam.md)")


def find_model(slam: str, kind: str, name: str = "best",
               models_dir: os.PathLike | str | None = None,
               setting: str | None = None) -> Path:
    """The folder of the model ``name`` (a folder under a searched directory, or a path) or,
    for ``best``, of the best model of card ``kind`` trained for ``slam`` (and, plan-only,
    for ``setting`` when given): in the first searched directory that has one, the default
    robot-aware folder first (robot-aware), then the highest card ``priority``, the most
    training buildings, the name. InputError (one line) when there is none, or when the named
    model was trained for another algorithm or setting."""
    dirs = search_dirs(models_dir)
    if name != "best":
        return check_trained_for(_named_folder(name, dirs), slam, setting)
    for folder in dirs:
        ranked = sorted(_candidates(folder, kind, slam, setting))
        if ranked:
            return ranked[0][-1]
    where = " or ".join(str(d) for d in dirs)
    what = "robot-aware model" if kind == ROBOT_KIND else "model"
    for_setting = f" for the {setting} setting" if setting and kind == PLAN_KIND else ""
    shipped = (f"; the package ships none for {slam}: docs/{slam}.md"
               if slam != DEFAULT_SLAM and SHIPPED_MODELS in dirs else "")
    raise InputError(f"no {what} of {slam}'s error{for_setting} in {where} (a card names "
                     f"its algorithm in 'slam', {DEFAULT_SLAM} when absent{shipped}); "
                     + train_hint(slam, kind))


def _candidates(folder: Path, kind: str, slam: str, setting: str | None):
    """(rank key..., path) of the model folders under ``folder`` that qualify."""
    preferred = DEFAULT_ROBOT_MODEL if kind == ROBOT_KIND else None
    for path in list_stores(folder):
        try:
            card = read_card(path)
        except InputError as exc:
            LOG.warning("skipping %s", exc.one_line())
            continue
        if kind_of(card) != kind or card_slam(card) != slam:
            continue
        if kind == PLAN_KIND and setting is not None and card["setting"] != setting:
            continue
        yield (path.name != preferred, -int(card.get("priority", 0)),
               -len(card["training_buildings"]), path.name, path)


def _named_folder(name: str, dirs: Sequence[Path]) -> Path:
    """The folder ``name`` means: a path, or the first searched directory holding it."""
    if os.sep in name or Path(name).is_dir():
        return Path(name)
    for folder in dirs:
        if (folder / name).exists():
            return folder / name
    names = sorted({p.name for d in dirs for p in list_stores(d)})
    raise InputError(f"no model named '{name}' in {' or '.join(str(d) for d in dirs)}"
                     + did_you_mean(name, names)
                     + (f" (available: {', '.join(names)})" if names else ""))


def check_trained_for(path: Path, slam: str, setting: str | None = None) -> Path:
    """``path`` when its card is trained for ``slam`` (and ``setting``, plan-only);
    InputError (one line) otherwise."""
    card = read_card(path)
    check_slam(slam, card, path / CARD)
    if setting is not None and kind_of(card) == PLAN_KIND and card["setting"] != setting:
        raise InputError(f"model was trained for the {card['setting']} setting, not "
                         f"{setting}", path / CARD)
    return path
