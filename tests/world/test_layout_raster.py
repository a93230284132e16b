"""Exact rasterisation (raster.py) against a slow shapely reference on seeded random shapes."""
from __future__ import annotations

import numpy as np
import pytest
import shapely
from shapely.geometry import LineString, Polygon

from slam_predict.world import raster
from slam_predict.world.model import World


def reference_mask(grid: raster.Grid, shape) -> np.ndarray:
    """Cells whose centre lies inside ``shape`` (shapely), the obviously-correct slow rule."""
    world = World("ref", np.zeros(grid.shape, bool), grid.resolution, origin=grid.origin)
    rr, cc = np.indices(grid.shape)
    centres = world.cell_to_world(np.stack([rr.ravel(), cc.ravel()], axis=1))
    inside = shapely.contains_xy(shape, centres[:, 0], centres[:, 1])
    return inside.reshape(grid.shape)


def random_polygon(rng: np.random.Generator) -> np.ndarray:
    """A star-shaped simple polygon around a random centre (m)."""
    n = int(rng.integers(3, 12))
    angles = np.sort(rng.uniform(0, 2 * np.pi, n))
    radii = rng.uniform(0.5, 2.5, n)
    centre = rng.uniform(-1.5, 1.5, 2)
    return centre + np.stack([radii * np.cos(angles), radii * np.sin(angles)], axis=1)


@pytest.mark.parametrize("seed", range(20))
def test_fill_polygons_matches_pixel_centre_reference(seed):
    rng = np.random.default_rng(seed)
    grid = raster.Grid(97, 83, 0.05 + 0.01 * (seed % 3), (rng.uniform(-1, 1), rng.uniform(-1, 1)))
    polygon = random_polygon(rng)
    mask = grid.empty()
    raster.fill_polygons(mask, grid, [polygon])
    expected = reference_mask(grid, Polygon(polygon))
    # cells whose centre lies exactly on an edge may go either way: allow only those
    differ = mask != expected
    assert differ.sum() <= 2, f"{differ.sum()} cells differ"


@pytest.mark.parametrize("seed", range(10))
def test_draw_segments_matches_square_cap_buffer(seed):
    rng = np.random.default_rng(100 + seed)
    grid = raster.Grid(80, 90, 0.05)
    segments = rng.uniform(-1.8, 1.8, (3, 2, 2))
    thickness = float(rng.uniform(0.1, 0.3))
    mask = grid.empty()
    raster.draw_segments(mask, grid, segments, thickness)
    shape = shapely.union_all([LineString(s).buffer(thickness / 2, cap_style="square",
                                                    join_style="mitre") for s in segments])
    expected = reference_mask(grid, shape)
    assert (mask != expected).sum() <= 3


def test_fill_box_and_integer_labels():
    grid = raster.Grid(10, 10, 1.0)
    mask = grid.empty()
    raster.fill_box(mask, grid, -2.0, -1.0, 3.0, 4.0)
    assert mask.sum() == 25
    assert mask[1:6, 3:8].all()  # y up: rows 1..5 are y 4..-1
    labels = np.zeros(grid.shape, dtype=np.int32)
    raster.fill_polygons(labels, grid, [np.array([[-5, -5], [0, -5], [0, 0], [-5, 0]])], 7)
    assert set(np.unique(labels)) == {0, 7} and (labels == 7).sum() == 25


def test_area_and_perimeter():
    square = np.array([[0, 0], [2, 0], [2, 3], [0, 3]], float)
    assert raster.polygon_area(square) == pytest.approx(6.0)
    assert raster.polygon_perimeter(square) == pytest.approx(10.0)


def test_grid_window_keeps_world_coordinates():
    grid = raster.Grid(40, 60, 0.1, (1.0, -2.0))
    sub = grid.window(5, 15, 20, 32)
    point = np.array([0.73, -1.37])
    full_uv = grid.to_px(point)
    sub_uv = sub.to_px(point)
    assert np.allclose(full_uv - sub_uv, [20, 5])


def test_nested_cells_share_the_extent():
    from slam_predict.world.layout_raster import nested_cells

    for size in (12.35, 12.349, 7.0, 0.04, 33.333):
        assert nested_cells(size, 0.05) == 2 * nested_cells(size, 0.1)
        assert nested_cells(size, 0.05, ceil=True) == 2 * nested_cells(size, 0.1, ceil=True)
    assert nested_cells(12.36, 0.1) == 124 and nested_cells(12.36, 0.05) == 248
    assert nested_cells(12.31, 0.1, ceil=True) == 124
    assert nested_cells(12.36, 0.03) == 412  # 0.03 does not divide 0.1: its own rounding


def random_layout(rng: np.random.Generator):
    """Two rooms side by side (random sizes, m) with no portal, and a random inner wall."""
    from slam_predict.world.model import Room

    x0, y0 = rng.uniform(-4, -2, 2)
    xm, x1, y1 = rng.uniform(-0.5, 0.5), rng.uniform(2, 4), rng.uniform(2, 4)
    rooms = [Room("A", np.array([[x0, y0], [xm, y0], [xm, y1], [x0, y1]])),
             Room("B", np.array([[xm, y0], [x1, y0], [x1, y1], [xm, y1]]))]
    wall = np.array([[[x0, rng.uniform(y0, y1)], [rng.uniform(x0, xm - 1.5), y0]]])
    return rooms, [wall]


@pytest.mark.parametrize("seed", range(12))
def test_sampled_rasterisation_commutes_with_any_reduction(seed):
    """Conservative rasterisation on 0.05 m samples: the 0.10 m/px raster is exactly the 2 x 2
    "any" reduction of the 0.05 m/px one (same centre and extent) by the features' working-grid
    resampler; the pixel-centre rule is not."""
    from slam_predict.world.bitmap import resample_square
    from slam_predict.world.layout_raster import rasterise, rasterise_sampled

    rng = np.random.default_rng(seed)
    rooms, walls = random_layout(rng)
    origin = tuple(rng.uniform(-0.3, 0.3, 2))
    fine, coarse = raster.Grid(200, 200, 0.05, origin), raster.Grid(100, 100, 0.1, origin)
    a, _, _ = rasterise_sampled(rooms, walls, [], fine, 0.15, 0.9, 0.05)
    b, inferred, report = rasterise_sampled(rooms, walls, [], coarse, 0.15, 0.9, 0.05)
    assert len(inferred) == 1 and report["samples_per_cell"] == 2
    assert np.array_equal(~resample_square(~a, (10.0, 10.0), 0.1), b)
    assert np.array_equal(a, rasterise(rooms, walls, [], fine, 0.15, 0.9)[0])
    plain, _, _ = rasterise(rooms, walls, [], coarse, 0.15, 0.9)
    assert (plain & ~b).any() and not (b & ~plain).any()  # walls only grow
