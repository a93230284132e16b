"""The full feature vector, its configuration and version."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from slam_predict.config import from_dict, load_config, to_dict
from slam_predict.errors import InputError
from slam_predict.features.vector import (
    REGISTRY,
    FeaturesConfig,
    compute_features,
    compute_with_context,
    feature_version,
    phase_worlds,
    working_world,
)

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
    assert base.startswith("2+") and base == feature_version(FeaturesConfig())
    changed = dataclasses.replace(FeaturesConfig(), mode="thesis_compatible")
    assert feature_version(changed) != base


def _shifted_reference(occupied, rows, cols):
    """Slow reference: half-cell pixels, padded by one on both sides of the shifted axes
    (border repeated), each new cell an obstacle when any of its 2x2 half-cell pixels is."""
    fine = occupied.repeat(2, 0).repeat(2, 1)
    fine = np.pad(fine, ((rows, rows), (cols, cols)), mode="edge")
    out = np.zeros((fine.shape[0] // 2, fine.shape[1] // 2), bool)
    for r in range(out.shape[0]):
        for c in range(out.shape[1]):
            out[r, c] = fine[2 * r:2 * r + 2, 2 * c:2 * c + 2].any()
    return out


def test_phase_worlds_match_reference():
    world = working_world(corridor_with_rooms(2).world(), 0.1)
    grids = phase_worlds(world, 4)
    assert grids[0] is world and len(grids) == 4 and len(phase_worlds(world, 2)) == 2
    for grid, (rows, cols) in zip(grids[1:], ((1, 1), (1, 0), (0, 1)), strict=False):
        np.testing.assert_array_equal(grid.occupied, _shifted_reference(world.occupied, rows, cols))
        assert grid.origin == world.origin and grid.resolution == world.resolution
    # the building stays in place: the start pose's cell is free on every grid
    for grid in grids:
        assert not grid.occupied[tuple(grid.world_to_cell(np.array(world.start_pose[:2])))]


def test_traversal_is_the_mean_over_grid_phases():
    world = corridor_with_rooms(3).world()
    config = FeaturesConfig(families=("voronoi_traversal",))
    values, ctx = compute_with_context(world, config)
    distances = [r.distance for r in ctx.phase_traversals]
    assert len(distances) == 4 and ctx.phase_traversals[0] is ctx.traversal
    assert values["voronoi_traversal_distance"] == pytest.approx(np.mean(distances))
    single = compute_features(world, dataclasses.replace(config, grid_phases=1))
    assert single["voronoi_traversal_distance"] == pytest.approx(distances[0])
    assert all(abs(d / distances[0] - 1) < 0.1 for d in distances)
    with pytest.raises(ValueError, match="grid_phases"):
        FeaturesConfig(grid_phases=3)


def test_progress_is_logged_per_family_and_shifted_grid(caplog):
    import logging

    world = corridor_with_rooms(3).world()
    with caplog.at_level(logging.INFO, logger="slam_predict.features.progress"):
        compute_features(world)
    messages = [r.getMessage() for r in caplog.records
                if r.name == "slam_predict.features.progress"]
    for i, family in enumerate(("geometric", "topological", "voronoi_graph",
                                "voronoi_traversal")):
        assert any(f": {family} features ({i + 1}/4, " in m for m in messages), messages
    assert sum("traversal on shifted grid" in m for m in messages) == 3


def test_degenerate_vectors_are_named():
    from slam_predict.features.vector import degenerate_reason

    values = compute_features(corridor_with_rooms(3).world())
    assert degenerate_reason(values) is None
    assert degenerate_reason(dict(values, voronoi_order=0.0)).startswith("no Voronoi graph")
    assert degenerate_reason(dict(values, voronoi_order=0.0, num_spaces=0.0)).startswith(
        "no Voronoi graph and no rooms")
    assert degenerate_reason({"building_area": 1.0}) is None  # families not computed


def test_features_describe_the_part_the_start_lies_in():
    """A door drawn closed between a 6 m x 10 m room (start) and a 12 m x 10 m one: the old
    outline (longest contour) was the larger room for either start, so the features described
    a room the robot never enters."""
    from slam_predict.world.model import World
    from slam_predict.world.start import resolve_start

    occupied = np.ones((102, 183), bool)
    occupied[1:-1, 1:61] = False
    occupied[1:-1, 62:182] = False
    world = World(name="closed", occupied=occupied, resolution=0.1, origin=(0.0, 0.0))
    areas = []
    for col in (30, 120):
        x, y = world.cell_to_world((50, col))
        areas.append(compute_features(resolve_start(world, [x, y]))["building_area"])
    assert areas == [pytest.approx(60.0), pytest.approx(120.0)]
