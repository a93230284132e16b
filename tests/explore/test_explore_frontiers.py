"""Frontier detection and clustering against slow references."""
from __future__ import annotations

from collections import deque
from types import SimpleNamespace

import numpy as np
import pytest

from slam_predict.explore.frontiers import clear_goal, find_frontiers, frontier_mask


def random_map(rng, shape=(50, 60)):
    data = np.full(shape, -1, np.int8)
    known = np.zeros(shape, bool)
    for _ in range(6):  # a few known rectangles
        r, c = rng.integers(0, shape[0] - 5), rng.integers(0, shape[1] - 5)
        known[r:r + rng.integers(4, 25), c:c + rng.integers(4, 30)] = True
    data[known] = 0
    data[known & (rng.random(shape) < 0.08)] = 100
    return data


def ref_mask(data):
    out = np.zeros(data.shape, bool)
    rows, cols = data.shape
    for r in range(rows):
        for c in range(cols):
            if data[r, c] != 0:
                continue
            for dr, dc in ((1, 0), (-1, 0), (0, 1), (0, -1)):
                rr, cc = r + dr, c + dc
                if 0 <= rr < rows and 0 <= cc < cols and data[rr, cc] == -1:
                    out[r, c] = True
    return out


def ref_clusters(mask):
    seen = np.zeros(mask.shape, bool)
    clusters = []
    for r, c in zip(*np.nonzero(mask), strict=False):
        if seen[r, c]:
            continue
        queue, cells = deque([(r, c)]), []
        seen[r, c] = True
        while queue:
            cr, cc = queue.popleft()
            cells.append((cr, cc))
            for dr in (-1, 0, 1):
                for dc in (-1, 0, 1):
                    rr, c2 = cr + dr, cc + dc
                    if (0 <= rr < mask.shape[0] and 0 <= c2 < mask.shape[1] and mask[rr, c2]
                            and not seen[rr, c2]):
                        seen[rr, c2] = True
                        queue.append((rr, c2))
        clusters.append(cells)
    return clusters


@pytest.mark.parametrize("seed", range(5))
def test_mask_and_clusters_match_references(seed):
    rng = np.random.default_rng(seed)
    data = random_map(rng)
    np.testing.assert_array_equal(frontier_mask(data), ref_mask(data))
    res, origin = 0.1, (-2.0, 1.0)
    grid = SimpleNamespace(data=data, resolution=res, origin=origin)
    robot = (0.5, 3.0)
    found = find_frontiers(grid, robot, min_frontier_size=0.35)
    expected = [c for c in ref_clusters(ref_mask(data)) if len(c) * res >= 0.35]
    assert sorted(f.size for f in found) == sorted(len(c) for c in expected)
    for f in found:
        cells = {(int(round((y - origin[1]) / res - 0.5)), int(round((x - origin[0]) / res - 0.5)))
                 for x, y in f.cells}
        assert any(cells == set(c) for c in expected)
        assert f.min_distance == pytest.approx(np.min(np.hypot(*(f.cells - robot).T)))
        np.testing.assert_allclose(f.centroid, f.cells.mean(axis=0))
        assert any(np.allclose(f.goal, cell) for cell in f.cells)
    assert [f.min_distance for f in found] == sorted(f.min_distance for f in found)


def test_no_frontier_when_fully_known_or_unknown():
    grid = SimpleNamespace(data=np.zeros((10, 10), np.int8), resolution=0.05, origin=(0, 0))
    assert find_frontiers(grid, (0, 0), 0.0) == []
    grid.data[:] = -1
    assert find_frontiers(grid, (0, 0), 0.0) == []


def test_clear_goal_keeps_away_from_walls():
    res = 0.05
    data = np.full((40, 60), -1, np.int8)
    data[:20, :] = 0                # known free below row 20, unknown above: frontier on row 19
    data[:, :3] = data[:, 55:] = 100
    data[15:19, 19:24] = 100        # a pillar just below the middle of the frontier
    grid = SimpleNamespace(data=data, resolution=res, origin=(0.0, 0.0))
    frontier = find_frontiers(grid, (1.0, 0.2), 0.5)[0]
    occupied = (np.argwhere(data == 100)[:, ::-1] + 0.5) * res          # (x, y) centres

    def clearance(p):
        return np.min(np.hypot(*(occupied - p).T))

    assert clearance(frontier.goal) < 0.5                     # the centroid cell is too close
    goal = clear_goal(frontier, grid, 0.5)
    assert clearance(goal) >= 0.5 - 1e-9
    free = (np.argwhere(data == 0)[:, ::-1] + 0.5) * res
    ok = [c for c in free if clearance(c) >= 0.5 - 1e-9]
    best = min(ok, key=lambda c: np.hypot(*(c - frontier.goal)))     # brute force
    np.testing.assert_allclose(goal, best)
    assert np.hypot(*(goal - frontier.goal)) <= 1.0
    np.testing.assert_allclose(clear_goal(frontier, grid, 0.0), frontier.goal)


def test_clear_goal_is_never_across_a_wall_from_its_frontier():
    """A narrow pocket (frontier at its top) behind a thin wall with open space below it: the
    open cells beyond the wall are nearer in a straight line but not joined to the frontier."""
    res = 0.05
    data = np.zeros((60, 60), np.int8)             # known free everywhere
    data[:, :2] = data[:, 58:] = data[:2, :] = 100
    data[30, :] = 100                               # a thin wall along row 30
    data[31:, 20:27] = 100                          # above it: a 0.35 m pocket between blocks
    data[31:, 34:] = 100
    data[31:, :20] = 100
    data[40:, 27:34] = -1                           # unknown beyond the pocket (row 40 up)
    grid = SimpleNamespace(data=data, resolution=res, origin=(0.0, 0.0))
    frontier = find_frontiers(grid, (1.5, 0.5), 0.2)[0]
    goal = clear_goal(frontier, grid, 0.5)
    row = int(goal[1] / res)
    assert row > 30                                 # on the frontier's side of the wall
    wall_y = 30.5 * res
    below = (np.argwhere((data == 0)[:30])[:, ::-1] + 0.5) * res
    assert np.min(np.hypot(*(below - frontier.goal).T)) <= 1.0   # the old choice existed
    assert frontier.goal[1] > wall_y


def test_clear_goal_falls_back_to_the_most_open_frontier_cell():
    res = 0.05
    data = np.full((30, 30), 100, np.int8)
    data[5:12, 5:25] = 0              # a 0.35 m wide closet: nothing is 0.5 m from its walls
    data[12, 5:25] = -1
    grid = SimpleNamespace(data=data, resolution=res, origin=(0.0, 0.0))
    frontier = find_frontiers(grid, (0.5, 0.4), 0.2)[0]
    goal = clear_goal(frontier, grid, 0.5)
    assert any(np.allclose(goal, c) for c in frontier.cells)


def grid_of(data, origin=(-2.0, 1.0), resolution=0.1):
    return SimpleNamespace(data=data, origin=origin, resolution=resolution)


@pytest.mark.parametrize("seed", range(4))
def test_cached_clusters_are_the_ones_searched_afresh(seed, monkeypatch):
    """The explorer's ClusterCache: frontiers from cached clusters equal a fresh search for
    every robot position, an unchanged map (even a new grid object) is not searched again, and
    a map changed in place, moved or of another resolution is."""
    from slam_predict.explore import frontiers as fr

    rng = np.random.default_rng(seed)
    cache, calls = fr.ClusterCache(), []
    real = fr.frontier_clusters

    def counting(*args):
        calls.append(1)
        return real(*args)

    monkeypatch.setattr(fr, "frontier_clusters", counting)
    data = random_map(rng)
    for robot in rng.uniform(-2.0, 5.0, (5, 2)):
        grid = grid_of(data.copy())                      # republished, same cells
        got = find_frontiers(grid, robot, 0.3, 0.0, cache.clusters(grid, 0.3, 0.0))
        want = find_frontiers(grid, robot, 0.3, 0.0)
        assert [f.min_distance for f in got] == [f.min_distance for f in want]
        for a, b in zip(got, want, strict=True):
            assert np.array_equal(a.cells, b.cells) and np.array_equal(a.goal, b.goal)
    assert len(calls) == 1 + 5        # one cached search; five fresh ones for `want`
    grid.data[grid.data == -1] = 0                       # changed in place
    assert cache.clusters(grid, 0.3, 0.0) == [] and len(calls) == 7
    for other in (grid_of(data, origin=(0.0, 0.0)), grid_of(data, resolution=0.05)):
        cache.clusters(other, 0.3, 0.0)
    assert len(calls) == 9
    cache.clusters(grid_of(data, resolution=0.05), 0.5, 0.0)   # another minimum size
    assert len(calls) == 10


@pytest.mark.parametrize("seed", range(4))
def test_known_box_of_an_int8_map_equals_the_generic_rule(seed):
    """known_box of an int8 map (one kernel pass) equals that of the same map as int16."""
    from slam_predict.explore.frontiers import known_box

    rng = np.random.default_rng(seed)
    data = random_map(rng) if seed else np.full((20, 30), -1, np.int8)
    for grow in (0, 1, 3):
        assert known_box(data, grow) == known_box(data.astype(np.int16), grow)
