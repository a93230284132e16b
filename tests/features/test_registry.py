"""Feature registry: names, units, descriptions, duplicates refused."""
from __future__ import annotations

import pytest

from slam_predict.errors import InputError
from slam_predict.features.registry import Registry
from slam_predict.features.vector import FAMILIES, REGISTRY


def test_duplicates_refused():
    reg = Registry()
    reg.add_family("a", lambda ctx: {}, [("x", "m", "an x")])
    with pytest.raises(ValueError, match="family 'a'"):
        reg.add_family("a", lambda ctx: {}, [("y", "m", "a y")])
    with pytest.raises(ValueError, match="feature 'x'"):
        reg.add_family("b", lambda ctx: {}, [("x", "m", "again")])
    with pytest.raises(ValueError, match="feature 'z'"):
        reg.add_family("c", lambda ctx: {}, [("z", "m", "z"), ("z", "m", "z twice")])
    with pytest.raises(ValueError, match="unit"):
        reg.add_family("d", lambda ctx: {}, [("w", "", "no unit")])
    assert reg.families == ["a"] and len(reg) == 1


def test_unknown_names_get_a_hint():
    with pytest.raises(InputError, match="did you mean 'voronoi_traversal_distance'"):
        REGISTRY.feature("voronoi_traversal_distanse")
    with pytest.raises(InputError, match="geometric"):
        REGISTRY.family("geometrix")


def test_the_shipped_registry():
    assert REGISTRY.families == list(FAMILIES)
    names = REGISTRY.names()
    assert len(names) == len(set(names)) == 43
    for name in names:
        feature = REGISTRY.feature(name)
        assert feature.unit and feature.doc
    assert REGISTRY.feature("voronoi_traversal_distance").unit == "m"
    assert REGISTRY.feature("voronoi_traversal_rotation").unit == "rad"
    assert REGISTRY.names(["voronoi_traversal"]) == [
        "voronoi_traversal_distance", "voronoi_traversal_rotation",
        "voronoi_traversal_rotation_smoothed"]
