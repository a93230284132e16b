"""One way to load a model folder of either family: :func:`load_model`.

The returned model predicts from a plan's feature vector (computed by
:func:`slam_predict.features.plan.plan_features` with the model's :attr:`feature_config` and
:attr:`sightline_config`) plus, for a robot-aware model, the robot's inputs; it never computes
plan features itself. A card names the SLAM algorithm its model was trained for
(:mod:`~slam_predict.learn.slam_choice`, which also picks the folder for an algorithm).

- :class:`PlanModel` (card kind ``plan``): :meth:`PlanModel.predict` gives the report form of
  each component (:func:`slam_predict.learn.predict.predict_features`); a robot is not an
  input (:attr:`takes_robot` False).
- :class:`~slam_predict.learn.robot.predict.RobotModel` (card kind ``robots``): raw values and
  intervals per component from the features and the robot inputs.
"""
from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from slam_predict.learn.card import (  # noqa: F401  (check_slam re-exported)
    CARD,
    PLAN_KIND,
    ROBOT_KIND,
    check_kind,
    check_slam,
    kind_of,
    read_card,
)
from slam_predict.learn.slam_choice import DEFAULT_SLAM, find_model
from slam_predict.learn.store import ModelStore


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

        check_slam(slam, self.store.card)
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


def resolve_store(models_dir: os.PathLike | str | None, name: str, setting: str | None,
                  feature_version: str | None, slam: str = DEFAULT_SLAM) -> ModelStore:
    """The plan-only model folder ``name`` (a name under ``models_dir`` or a path), or the
    best one for ``setting``, trained for SLAM algorithm ``slam``.

    ``best``: among the compatible stores, the highest ``priority`` in the card, then the most
    training buildings, then the name; ``models_dir`` None searches ``$SLAM_PREDICT_MODELS``
    and the package's ``models/`` (:func:`slam_predict.learn.slam_choice.find_model`).
    """
    path = find_model(slam, PLAN_KIND, name, models_dir, setting)
    return load_model(path, PLAN_KIND, feature_version).store
