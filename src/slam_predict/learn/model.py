"""One way to load a model folder of either family: :func:`load_model`.

The returned model predicts from a plan's feature vector (computed by
:func:`slam_predict.features.plan.plan_features` with the model's :attr:`feature_config` and
:attr:`sightline_config`) plus, for a robot-aware model, the robot's inputs; it never computes
plan features itself. Both families take an optional SLAM algorithm name, which must be the
one the card records (``slam``; gmapping when absent) or absent.

- :class:`PlanModel` (card kind ``plan``): :meth:`PlanModel.predict` gives the report form of
  each component (:func:`slam_predict.learn.predict.predict_features`); a robot is not an
  input (:attr:`takes_robot` False).
- :class:`~slam_predict.learn.robot.predict.RobotModel` (card kind ``robots``): raw values and
  intervals per component from the features and the robot inputs.
"""
from __future__ import annotations

import logging
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from slam_predict.errors import InputError, did_you_mean
from slam_predict.learn.card import (  # noqa: F401  (check_slam re-exported)
    CARD,
    PLAN_KIND,
    ROBOT_KIND,
    card_slam,
    check_kind,
    check_slam,
    kind_of,
    read_card,
)
from slam_predict.learn.store import ModelStore, list_stores

LOG = logging.getLogger(__name__)


class PlanModel:
    """A loaded plan-only model folder: plan features → the four components."""

    takes_robot = False

    def __init__(self, store: ModelStore):
        self.store = store
        self.card = store.card

    @property
    def name(self) -> str:
        return self.store.name

    @property
    def notes(self) -> list[str]:
        """Warnings of the loading (another scikit-learn minor version…)."""
        return self.store.notes

    @property
    def feature_config(self) -> dict[str, Any]:
        """The card's feature configuration (give it to ``plan_features``)."""
        return dict(self.card.get("feature_config") or {})

    @property
    def sightline_config(self) -> None:
        """Plan-only models read no sight-line columns."""
        return None

    def check_feature_version(self) -> None:
        """InputError unless this installation computes the card's feature version."""
        from slam_predict.learn.predict import check_feature_version

        check_feature_version(self.store)

    def predict(self, features: Mapping[str, float], robot: Mapping[str, float] | None = None,
                slam: str | None = None, component: str = "all") -> dict[str, Any]:
        """The report form of ``component`` (``all``: the four) for one feature vector; a
        plan-only model does not read ``robot``."""
        from slam_predict.learn.predict import predict_features

        check_slam(slam, self.card)
        return predict_features(dict(features), self.store, component)


def load_model(path: os.PathLike | str, kind: str | None = None,
               feature_version: str | None = None):
    """The model folder at ``path`` as a :class:`PlanModel` or a
    :class:`~slam_predict.learn.robot.predict.RobotModel`, by its card's kind; ``kind``
    (``plan`` or ``robots``) refuses the other family with a one-line InputError naming it.
    Checks the card, every file's checksum and scikit-learn's major version."""
    card = read_card(path)
    if kind is not None:
        check_kind(card, kind, Path(path) / CARD)
    if kind_of(card) == ROBOT_KIND:
        from slam_predict.learn.robot.predict import RobotModel

        return RobotModel.load(path)
    check_kind(card, PLAN_KIND, Path(path) / CARD)
    return PlanModel(ModelStore(path, feature_version))


def resolve_store(models_dir: os.PathLike | str, name: str, setting: str | None,
                  feature_version: str | None, slam: str | None = None) -> ModelStore:
    """The model folder ``name`` (a name under ``models_dir`` or a path), or the best one.

    ``best``: among the compatible stores for ``setting`` (and trained on SLAM algorithm
    ``slam`` when given), the highest ``priority`` in the card, then the most training
    buildings, then the name. A named folder must have been trained on ``slam`` when given.
    """
    models_dir = Path(models_dir)
    if name != "best":
        path = Path(name) if (os.sep in name or Path(name).is_dir()) else models_dir / name
        if not path.exists() and os.sep not in name:
            names = [p.name for p in list_stores(models_dir)]
            raise InputError(f"no model named '{name}' in {models_dir}" + did_you_mean(name, names)
                             + (f" (available: {', '.join(names)})" if names else ""))
        store = load_model(path, PLAN_KIND, feature_version).store
        if setting is not None and store.card["setting"] != setting:
            raise InputError(f"model was trained for the {store.card['setting']} setting, not "
                             f"{setting}", path / CARD)
        check_slam(slam, store.card)
        return store
    candidates = []
    for path in list_stores(models_dir):
        try:
            card = read_card(path)
        except InputError as exc:
            LOG.warning("skipping %s", exc.one_line())
            continue
        if kind_of(card) == PLAN_KIND and (setting is None or card["setting"] == setting) \
                and (slam is None or card_slam(card) == slam):
            candidates.append((-int(card.get("priority", 0)),
                               -len(card["training_buildings"]), path.name, path))
    if not candidates:
        of = f" of SLAM algorithm {slam}" if slam else ""
        raise InputError(f"no trained model{of} for the {setting} setting in {models_dir}; train "
                         "one with 'slam-predict learn train'")
    return load_model(sorted(candidates)[0][3], PLAN_KIND, feature_version).store


def trained_slams(models_dir: os.PathLike | str) -> list[str]:
    """The SLAM algorithms the readable model folders of ``models_dir`` were trained on."""
    slams = set()
    for path in list_stores(Path(models_dir)):
        try:
            slams.add(card_slam(read_card(path)))
        except InputError as exc:
            LOG.warning("skipping %s", exc.one_line())
    return sorted(slams)
