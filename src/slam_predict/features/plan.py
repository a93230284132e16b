"""A plan's feature vector under a stored feature configuration: what a model reads of a plan.

``predict`` runs one way: world/ loads and checks the plan, this module computes every
feature a model reads (:func:`plan_features`: the feature vector of
:func:`slam_predict.features.vector.compute_features` under the model card's feature
configuration and, when the model reads them, the sight-line / floor-shape columns of
:func:`slam_predict.features.sightline.sightline_features`), and learn/ predicts from that
vector. The stored configuration is a plain dict (model card, dataset sidecar); keys renamed
since are read silently. The feature version is the definition version plus the hash of the
full configuration (:func:`version_of`), so models refuse vectors computed differently.
"""
from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from slam_predict.errors import InputError


def feature_config(overrides: Mapping[str, Any] | None = None, source: str = "features"):
    """A :class:`FeaturesConfig` from a plain dict (defaults for missing keys)."""
    from slam_predict.config import from_dict
    from slam_predict.features.vector import FeaturesConfig

    return from_dict(FeaturesConfig, dict(overrides or {}), source)


def full_feature_config(overrides: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """The complete feature configuration (defaults + ``overrides``) as a plain dict."""
    from slam_predict.config import to_dict

    return to_dict(feature_config(overrides))


def stored_feature_config(config_dict: Mapping[str, Any]):
    """A :class:`FeaturesConfig` from a configuration the code stored (model card, dataset
    sidecar); keys renamed since are read silently (the user's files warn instead)."""
    from slam_predict.features.traversal import upgrade_stored

    config = dict(config_dict)
    if isinstance(config.get("traversal"), Mapping):
        config["traversal"] = upgrade_stored(config["traversal"])
    return feature_config(config)


def version_of(config_dict: Mapping[str, Any]) -> str:
    """The feature version (definition + configuration hash) of a stored feature configuration."""
    from slam_predict.features.vector import feature_version

    return feature_version(stored_feature_config(config_dict))


def compute(world, config_dict: Mapping[str, Any]) -> dict[str, float]:
    """The feature vector of ``world`` under the stored configuration ``config_dict``."""
    from slam_predict.features.vector import compute_features

    values = compute_features(world, stored_feature_config(config_dict))
    return {k: float(v) for k, v in values.items()}


def plan_features(world, config_dict: Mapping[str, Any] | None,
                  sightline: Mapping[str, Any] | None = None) -> dict[str, float]:
    """Every feature a model reads of ``world``: the vector under ``config_dict``
    (InputError when it is degenerate: no Voronoi graph, no rooms, nothing to predict from)
    plus, when ``sightline`` (a :class:`~slam_predict.features.sightline.SightlineConfig` as a
    dict) is given, the sight-line curve, ``sightline_isotropy`` and ``floor_elongation``."""
    from slam_predict.features.vector import degenerate_reason

    features = compute(world, config_dict or {})
    reason = degenerate_reason(features)
    if reason:
        raise InputError(f"{reason}: nothing to predict from", world.provenance.get("source"))
    if sightline is not None:
        from slam_predict.features.sightline import SightlineConfig, sightline_features

        features.update(sightline_features(world, SightlineConfig(**sightline)))
    return features
