"""Frontiers in the free space joined to the robot (explore_lite's search), against slow
references."""
from __future__ import annotations

from collections import deque
from types import SimpleNamespace

import numpy as np
import pytest

from slam_predict.explore.frontiers import ClusterCache
from slam_predict.explore.kernels import free_component


def grid_of(data, origin=(-1.0, -2.0), resolution=0.1):
    return SimpleNamespace(data=data, origin=origin, resolution=resolution)


def ref_component(data, row, col):
    """Breadth-first search over all cells from (row, col) to the first free cell, then every
    free cell 4-connected to it; slow and plain."""
    h, w = data.shape
    steps = ((-1, 0), (1, 0), (0, -1), (0, 1))
    queue, seen, start = deque([(row, col)]), {(row, col)}, None
    while queue:
        r, c = queue.popleft()
        if data[r, c] == 0:
            start = (r, c)
            break
        for dr, dc in steps:
            n = (r + dr, c + dc)
            if 0 <= n[0] < h and 0 <= n[1] < w and n not in seen:
                seen.add(n)
                queue.append(n)
    out = np.zeros(data.shape, bool)
    if start is None:
        return out
    out[start] = True
    queue = deque([start])
    while queue:
        r, c = queue.popleft()
        for dr, dc in steps:
            rr, cc = r + dr, c + dc
            if 0 <= rr < h and 0 <= cc < w and data[rr, cc] == 0 and not out[rr, cc]:
                out[rr, cc] = True
                queue.append((rr, cc))
    return out


@pytest.mark.parametrize("seed", range(8))
def test_free_component_matches_the_reference(seed):
    rng = np.random.default_rng(seed)
    data = rng.choice(np.array([-1, 0, 100], np.int8), size=(40, 55), p=[0.25, 0.5, 0.25])
    for row, col in rng.integers(0, (40, 55), (6, 2)):
        assert np.array_equal(free_component(data, row, col), ref_component(data, row, col))


def test_no_free_cell_gives_an_empty_component():
    data = np.full((5, 6), 100, np.int8)
    assert not free_component(data, 2, 3).any()


def wall_pocket_map():
    """A 3 m room (free) whose east wall (occupied column) has a free strip behind it, then
    unknown: the strip's frontier is cut off from the room; the room's north edge is open to
    unknown space (a real frontier)."""
    data = np.full((40, 40), -1, np.int8)
    data[5:35, 5:30] = 0          # the room, free
    data[4, 5:30] = 100           # south wall; the north edge (row 34) borders unknown
    data[5:35, 4] = 100           # west wall
    data[5:35, 30] = 100          # east wall, unbroken
    data[5:35, 31:33] = 0         # a free strip inside the wall, unknown beyond (col 33)
    return data


def test_a_frontier_behind_an_unbroken_wall_is_not_reachable():
    data = wall_pocket_map()
    grid = grid_of(data)
    cache = ClusterCache()
    everything = cache.clusters(grid, 0.3, 0.0)
    robot = (-1.0 + 15.5 * 0.1, -2.0 + 15.5 * 0.1)            # cell (15, 15), in the room
    reachable = cache.reachable(grid, robot)
    assert len(reachable) < len(everything)
    in_strip = [c for c in everything if c.cells[:, 0].min() > -1.0 + 31 * 0.1]
    kept = {id(c) for c in reachable}
    assert in_strip and all(id(c) not in kept for c in in_strip)
    assert reachable and all(c.cells[:, 0].max() < -1.0 + 30 * 0.1 for c in reachable)
    inside = (-1.0 + 31.5 * 0.1, -2.0 + 15.5 * 0.1)           # a robot in the strip
    assert [id(c) for c in cache.reachable(grid, inside)] == [id(c) for c in in_strip]


def test_a_gap_in_the_wall_joins_the_strip():
    data = wall_pocket_map()
    data[20, 30] = 0              # one free cell through the east wall
    grid = grid_of(data)
    cache = ClusterCache()
    everything = cache.clusters(grid, 0.3, 0.0)
    got = cache.reachable(grid, (0.55, -0.45))
    assert [id(c) for c in got] == [id(c) for c in everything]


def test_a_robot_on_an_occupied_cell_starts_from_the_nearest_free_cell():
    data = wall_pocket_map()
    grid = grid_of(data)
    cache = ClusterCache()
    cache.clusters(grid, 0.3, 0.0)
    on_the_east_wall_row_10 = (-1.0 + 30.5 * 0.1, -2.0 + 10.5 * 0.1)
    # cells (10, 29) in the room and (10, 31) in the strip are both one step away; the search
    # visits the row above, the row below, then the west and east neighbours (explore_lite's
    # nhood4 order differs; either is a nearest free cell)
    got = cache.reachable(grid, on_the_east_wall_row_10)
    assert got and len({id(c) for c in got}) == len(got)
