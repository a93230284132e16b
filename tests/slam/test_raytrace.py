"""Published-map ray tracing: Bresenham cells and the rebuild against slow references."""
import math

import numpy as np
import pytest
from slam_scan import ANGLES, scan_of

from slam_predict.slam.gmapping import raytrace
from slam_predict.slam.gmapping.gridmap import MapBuilder
from slam_predict.slam.gmapping.maps import Geometry
from slam_predict.slam.gmapping.params import GMappingParams, with_ranges


def slow_line(x0, y0, x1, y1):
    """Textbook integer Bresenham walked from the end with the smaller major coordinate."""
    steep = abs(y1 - y0) > abs(x1 - x0)
    a0, b0, a1, b1 = (y0, x0, y1, x1) if steep else (x0, y0, x1, y1)
    if a0 > a1:
        a0, b0, a1, b1 = a1, b1, a0, b0
    da, db = a1 - a0, abs(b1 - b0)
    step = 1 if b1 > b0 else -1
    err = 2 * db - da
    b = b0
    pts = []
    for a in range(a0, a1 + 1):
        pts.append((b, a) if steep else (a, b))
        if err >= 0 and a < a1:
            b += step
            err += 2 * (db - da)
        elif a < a1:
            err += 2 * db
    if pts[0] != (x0, y0):
        pts.reverse()
    return pts


@pytest.mark.parametrize("seed", range(4))
def test_line_cells_match_bresenham(seed):
    rng = np.random.default_rng(seed)
    for _ in range(200):
        x0, y0, x1, y1 = (int(v) for v in rng.integers(-40, 40, 4))
        got = [tuple(c) for c in raytrace.line_cells(x0, y0, x1, y1)]
        assert got == slow_line(x0, y0, x1, y1)
        assert got[0] == (x0, y0) and got[-1] == (x1, y1)


def slow_rebuild(params, poses, readings, geometry):
    """Dict-of-cells reference of updateMap's registration (generateMap=true)."""
    hits, visits = {}, {}
    for (x, y, th), ranges in zip(poses, readings, strict=False):
        start = geometry.world_to_cell(x, y)
        for r, a in zip(ranges, ANGLES, strict=False):
            if r > params.maxRange or r == 0.0:
                continue
            d = min(r, params.maxUrange)
            end = geometry.world_to_cell(x + d * math.cos(th + a), y + d * math.sin(th + a))
            for cell in slow_line(*start, *end)[:-1]:
                visits[cell] = visits.get(cell, 0) + 1
            if d < params.maxUrange:
                hits[end] = hits.get(end, 0) + 1
                visits[end] = visits.get(end, 0) + 1
    width, height = geometry.size
    data = np.full((height, width), -1, dtype=np.int8)
    for (ix, iy), v in visits.items():
        occ = hits.get((ix, iy), 0) / v
        data[iy, ix] = 100 if occ > params.occ_thresh else 0
    return data


def test_map_rebuild_matches_a_slow_reference():
    params = with_ranges(GMappingParams(xmin=-6, ymin=-5, xmax=6, ymax=5, maxUrange=4.0,
                                        maxRange=9.0), math.nan)
    poses = np.array([(-3.0, -2.0, 0.4), (0.0, -2.5, 1.2), (3.0, 0.0, 2.8), (-2.0, 2.0, -1.0)])
    readings = np.array([scan_of(p) for p in poses])
    readings[:, ::13] = 0.0
    readings[:, ::29] = 30.0  # beyond maxRange: dropped
    builder = MapBuilder(params, ANGLES)
    grid = builder.build(poses, readings)
    geometry = Geometry.bounded(-6, -5, 6, 5, 0.05)
    assert (grid.width, grid.height) == geometry.size
    assert grid.origin == geometry.cell_to_world(0, 0) == (-6.0, -5.0)
    ref = slow_rebuild(params, poses, readings, geometry)
    assert np.array_equal(grid.data, ref)
    assert (grid.data == 100).sum() > 50 and (grid.data == 0).sum() > 1000


def test_rebuild_grows_and_remembers_bounds():
    params = with_ranges(GMappingParams(xmin=-2, ymin=-2, xmax=2, ymax=2), 30.0)
    builder = MapBuilder(params, ANGLES)
    poses = np.array([(0.0, 0.0, 0.0)])
    grid = builder.build(poses, np.array([scan_of(poses[0])]))
    assert grid.width > 80 and builder.bounds[0] == -2.0 and builder.bounds[2] > 12.0
    assert builder.bounds[1] < -12.0 and builder.bounds[3] > 12.0  # beams reach y = ±4
    again = builder.build(poses, np.array([scan_of(poses[0])]))
    assert np.array_equal(grid.data, again.data) and grid.origin == again.origin
