"""Geometric features on plans with known areas and perimeters."""
from __future__ import annotations

import numpy as np
import pytest

from slam_predict.features.geometric import GeometryConfig, geometric_features, wall_ratio
from slam_predict.features.rooms import segment
from slam_predict.features.voronoi import building_interior

from .plans import Plan, corridor_with_rooms, single_room


def _features(plan):
    world = plan.world()
    interior = building_interior(~world.occupied)
    return geometric_features(interior, segment(world.occupied, world.resolution),
                              world.resolution)


def test_single_room():
    values = _features(single_room(10.0, 6.0))
    assert values["building_area"] == pytest.approx(60.0, rel=0.01)
    assert values["building_perimeter"] == pytest.approx(32.0, abs=0.3)
    assert values["wall_ratio"] == pytest.approx(0.6, abs=0.01)
    assert values["num_spaces"] == 1.0
    assert values["avg_space_area"] == pytest.approx(60.0, rel=0.01)
    assert values["total_space_perimeter"] == pytest.approx(values["building_perimeter"])


def test_l_shaped_building():
    plan = Plan(11.0, 11.0).room("a", (0.5, 0.5, 10.5, 4.5)).room("b", (0.5, 4.5, 4.5, 10.5))
    values = _features(plan)
    assert values["building_area"] == pytest.approx(10 * 4 + 4 * 6, rel=0.01)
    assert values["building_perimeter"] == pytest.approx(40.0, abs=0.4)
    assert values["wall_ratio"] == pytest.approx(4.0 / 10.0, abs=0.02)


def test_corridor_with_rooms():
    values = _features(corridor_with_rooms(4))
    assert values["num_spaces"] == 5.0
    rooms_area = 4 * 16.0
    assert values["avg_space_area"] * 5 == pytest.approx(rooms_area + 4 * 0.9 * 0.2 + 17.6 * 2,
                                                         rel=0.03)


def test_wall_ratio_ignores_short_edges():
    square = np.array([[0, 0], [4, 0], [4, 2], [4.1, 2], [4.1, 4], [0, 4]], float)
    assert wall_ratio(square, 0.5) == pytest.approx(2.0 / 4.1)
    assert wall_ratio(square, 10.0) == 0.0
    assert GeometryConfig().min_wall_m == 0.5
