"""features.plan: every feature a model reads of a plan, computed in features/ only."""
from __future__ import annotations

import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.features.plan import compute, full_feature_config, plan_features, version_of
from slam_predict.features.sightline import SightlineConfig, sightline_features
from slam_predict.features.vector import FeaturesConfig, compute_features, feature_version
from slam_predict.world.model import World

from .plans import corridor_with_rooms


def test_plan_features_are_the_vector_plus_the_requested_sight_lines():
    world = corridor_with_rooms(3).world()
    vector = compute_features(world, FeaturesConfig())
    plain = plan_features(world, {})
    assert plain == {k: float(v) for k, v in vector.items()} == compute(world, {})
    sampling = {"spacing_m": 1.0, "beams": 36}
    both = plan_features(world, {}, sampling)
    expected = dict(plain, **sightline_features(world, SightlineConfig(**sampling)))
    assert both == expected and list(both)[:len(plain)] == list(plain)


def test_a_plan_without_rooms_or_voronoi_graph_is_refused_naming_its_file():
    occupied = np.ones((60, 60), dtype=bool)
    occupied[10:50, 10:50] = np.random.default_rng(0).random((40, 40)) < 0.5   # noise
    world = World("noise", occupied, 0.05, start_pose=np.array([0.0, 0.0, 0.0]),
                  provenance={"source": "noise.png"})
    with pytest.raises(InputError, match="nothing to predict from") as err:
        plan_features(world, {})
    assert "noise.png" in err.value.one_line()


def test_version_of_a_stored_configuration_is_the_full_configurations():
    assert version_of({}) == version_of(full_feature_config({})) == feature_version(
        FeaturesConfig())
