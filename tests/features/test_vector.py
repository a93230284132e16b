"""The full feature vector, its configuration and version."""
from __future__ import annotations

import dataclasses
import math

import pytest

from slam_predict.config import from_dict, load_config, to_dict
from slam_predict.errors import InputError
from slam_predict.features.vector import (REGISTRY, FeaturesConfig, compute_features,
                                          compute_with_context, feature_version, working_world)

from .plans import corridor_with_rooms, four_rooms_cycle


def test_vector_has_every_registered_feature():
    world = corridor_with_rooms(3).world()
    values = compute_features(world)
    assert list(values) == REGISTRY.names()
    assert all(isinstance(v, float) and math.isfinite(v) for v in values.values())
    assert values["num_spaces"] == 4.0 and values["topology_order"] == 4.0
    assert values["voronoi_traversal_distance"] > 0


def test_families_subset_and_modes():
    world = four_rooms_cycle().world()
    config = FeaturesConfig(families=("voronoi_traversal",), mode="thesis_compatible")
    values, ctx = compute_with_context(world, config)
    assert list(values) == REGISTRY.names(["voronoi_traversal"])
    steps = ctx.voronoi.weights / ctx.world.resolution
    assert (abs(steps - steps.round()) < 1e-9).all()  # the seed's unit pixel steps
    assert config.voronoi_config().thesis_compatible
    assert config.traversal_config().mode == "thesis_compatible"


def test_working_grid():
    world = corridor_with_rooms(2).world()
    coarse = working_world(world, 0.1)
    assert coarse.resolution == 0.1 and coarse.shape[0] == round(world.shape[0] / 2)
    assert working_world(world, 0.0) is world
    assert working_world(coarse, 0.1) is coarse
    a = compute_features(world)
    b = compute_features(world, FeaturesConfig(working_resolution_m=0.0))
    assert a["num_spaces"] == b["num_spaces"]
    assert a["building_area"] == pytest.approx(b["building_area"], rel=0.02)


def test_path_is_in_world_metres():
    world = corridor_with_rooms(2).world()
    _, ctx = compute_with_context(world)
    xy = ctx.path_xy()
    assert xy.shape[1] == 2
    assert abs(xy[0] - world.start_pose[:2]).max() < 1.5  # starts near the start pose


def test_config_file_matches_defaults(root):
    loaded = load_config(FeaturesConfig, root / "config" / "features.yaml", "features")
    assert loaded == FeaturesConfig()
    assert from_dict(FeaturesConfig, to_dict(FeaturesConfig())) == FeaturesConfig()


def test_config_errors():
    with pytest.raises(InputError, match="did you mean 'laser_range_m'"):
        from_dict(FeaturesConfig, {"traversal": {"laser_rang_m": 10}})
    with pytest.raises(InputError, match="mode"):
        from_dict(FeaturesConfig, {"mode": "exact"})
    with pytest.raises(InputError, match="unknown feature family"):
        FeaturesConfig(families=("geometry",))


def test_version_follows_config():
    base = feature_version()
    assert base.startswith("1+") and base == feature_version(FeaturesConfig())
    changed = dataclasses.replace(FeaturesConfig(), mode="thesis_compatible")
    assert feature_version(changed) != base
