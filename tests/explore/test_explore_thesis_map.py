"""The thesis explorer's costmap and per-cell rules against slow cell-by-cell references."""
from __future__ import annotations

import math

import numpy as np
import pytest

from slam_predict.explore.thesis_map import (
    LETHAL,
    NO_INFORMATION,
    Costmap,
    backoff_goal,
    coarsen,
    explorer_costmap,
    frontier_cells,
    inflate,
    seen_mask,
)
from slam_predict.slam import OccupancyGrid


def random_occupancy(rng, shape=(30, 40)):
    data = np.zeros(shape, np.int8)
    data[rng.random(shape) < 0.3] = -1
    data[rng.random(shape) < 0.04] = 100
    return data


def test_coarsen_matches_a_block_by_block_reference():
    rng = np.random.default_rng(0)
    data = random_occupancy(rng, (9, 11))
    out = coarsen(data, 2)
    assert out.shape == (5, 6)
    for r in range(5):
        for c in range(6):
            block = data[2 * r:2 * r + 2, 2 * c:2 * c + 2]
            want = 100 if (block >= 50).any() else 0 if (block >= 0).any() else -1
            assert out[r, c] == want


@pytest.mark.parametrize("seed", [1, 2])
def test_inflation_matches_costmap_2d_formula_cell_by_cell(seed):
    rng = np.random.default_rng(seed)
    data = random_occupancy(rng)
    res, r_in, r_inf, k = 0.1, 0.15, 2.25, 7.5
    cost = inflate(data, res, r_in, r_inf, k)
    lethal = np.argwhere(data == 100)
    for (r, c), value in np.ndenumerate(data):
        d = min(math.hypot(r - lr, c - lc) for lr, lc in lethal) * res
        if value == 100:
            want = LETHAL
        elif d <= r_in:
            want = 253
        elif value == -1:
            want = NO_INFORMATION
        elif d <= r_inf:
            want = int(252 * math.exp(-k * (d - r_in)))
        else:
            want = 0
        assert cost[r, c] == want, (r, c)


def slow_frontier(cost, r, c):
    """isFrontier, written out: cost 0, an unknown and no lethal among the 16 neighbours."""
    if cost[r, c] != 0:
        return False
    steps = [(0, -1), (-1, 0), (0, 1), (1, 0), (-1, -1), (-1, 1), (1, 1), (1, -1)]
    unknown = lethal = False
    for k in (1, 2):
        for dr, dc in steps:
            rr, cc = r + k * dr, c + k * dc
            if 0 <= rr < cost.shape[0] and 0 <= cc < cost.shape[1]:
                unknown |= cost[rr, cc] == NO_INFORMATION
                lethal |= cost[rr, cc] == LETHAL
    return unknown and not lethal


@pytest.mark.parametrize("seed", [3, 4])
def test_frontier_cells_match_the_slow_rule_in_index_order(seed):
    rng = np.random.default_rng(seed)
    cost = rng.choice(np.array([0, 0, 0, 30, 253, 254, 255], np.uint8), size=(25, 35))
    cm = Costmap(cost, (-1.0, 2.0), 0.1)
    want = [(-1.0 + (c + 0.5) * 0.1, 2.0 + (r + 0.5) * 0.1)
            for r in range(25) for c in range(35) if slow_frontier(cost, r, c)]
    assert len(want) > 5
    np.testing.assert_allclose(frontier_cells(cm), np.array(want))


def test_seen_mask_matches_the_slow_rule():
    rng = np.random.default_rng(5)
    cost = rng.choice(np.array([0, 100, 254, 255], np.uint8), size=(30, 30),
                      p=[0.6, 0.1, 0.01, 0.29])
    cm = Costmap(cost, (0.0, 0.0), 0.1)
    points = rng.uniform(0.0, 3.0, size=(60, 2))
    got = seen_mask(cm, points, 6)
    for (x, y), flag in zip(points, got, strict=False):
        r, c = int(y // 0.1), int(x // 0.1)
        cells = [(r, c + k) for k in range(1, 7)] + [(r, c - k) for k in range(1, 7)] + \
            [(r + k, c) for k in range(1, 7)] + [(r - k, c) for k in range(1, 7)]
        costs = [cost[a, b] if 0 <= a < 30 and 0 <= b < 30 else LETHAL for a, b in cells]
        want = (NO_INFORMATION not in costs) or (LETHAL in costs) or (0 not in costs)
        assert flag == want
    assert got.any() and not got.all()


def test_backoff_takes_the_first_acceptable_axis_cell_clear_of_costly_cells():
    cost = np.zeros((41, 41), np.uint8)
    cm = Costmap(cost, (0.0, 0.0), 0.1)
    centre = (2.05, 2.05)                       # cell (20, 20)
    np.testing.assert_allclose(backoff_goal(cm, *centre, 40, 5, 50), [2.15, 2.05])
    cost[20, 21:30] = 60      # +x cells costly; -x has one 2 steps right of it: +y is next
    np.testing.assert_allclose(backoff_goal(cm, *centre, 40, 5, 50), [2.05, 2.15])
    cost[24, 20] = 254        # within 5 cells of +y and -y at 1 step, +y at 2: -y at 2 steps
    np.testing.assert_allclose(backoff_goal(cm, *centre, 40, 5, 50), [2.05, 1.85])
    cost[:, :] = 255                            # unknown is acceptable
    np.testing.assert_allclose(backoff_goal(cm, *centre, 40, 5, 50), [2.15, 2.05])
    cost[:, :] = 100                            # nothing acceptable
    assert backoff_goal(cm, *centre, 40, 5, 50) is None


def test_explorer_costmap_of_a_room_has_frontier_cells_only_far_from_walls():
    data = np.full((120, 120), -1, np.int8)
    data[20:80, 20:80] = 0                      # a 3 m x 3 m known room at 0.05 m
    data[20:80, 20] = 100
    data[20, 20:80] = 100                       # two walls; the other sides open to unknown
    grid = OccupancyGrid(data, 0.05, (-3.0, -3.0))
    cm = explorer_costmap(grid, 0.1, 0.2, 2.25, 7.5)
    assert cm.resolution == pytest.approx(0.1)
    cells = frontier_cells(cm)
    assert len(cells) > 10
    wall_x, wall_y = -3.0 + 20 * 0.05, -3.0 + 20 * 0.05
    assert np.min(cells[:, 0] - wall_x) > 0.93 and np.min(cells[:, 1] - wall_y) > 0.93
    assert np.max(cells[:, 0]) < -3.0 + 80 * 0.05 and np.max(cells[:, 1]) < -3.0 + 80 * 0.05
