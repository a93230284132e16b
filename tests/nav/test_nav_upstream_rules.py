"""TrajectoryPlannerConfig.upstream_rules: the five rules as noetic-devel's base_local_planner
has them (bench/bench_nav_diff.py checks them against the real library; these tests check each
rule against a plain reference or a hand-worked case)."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from slam_predict.config import config_hash
from slam_predict.nav.config import TrajectoryPlannerConfig
from slam_predict.nav.costmap import INSCRIBED, Costmap
from slam_predict.nav.footprint_helper import footprint_cells_upstream, outline_and_fill
from slam_predict.nav.map_grid import DistanceGrids
from slam_predict.nav.planner_modes import Oscillation
from slam_predict.nav.trajectory_planner import TrajectoryPlanner

RES = 0.05
SQUARE = np.array([[-0.21, -0.21], [-0.21, 0.21], [0.21, 0.21], [0.21, -0.21]])


def reference_line(x0, y0, x1, y1):
    """Bresenham written from its textbook form: step the major axis every cell, the minor one
    when the accumulated error passes half a step."""
    dx, dy = x1 - x0, y1 - y0
    n = max(abs(dx), abs(dy))
    sx, sy = (1 if dx >= 0 else -1), (1 if dy >= 0 else -1)
    out, err = [], n // 2
    x, y = x0, y0
    for _ in range(n + 1):
        out.append((x, y))
        err += min(abs(dx), abs(dy))
        if abs(dx) >= abs(dy):
            x += sx
            if err >= n:
                err -= n
                y += sy
        else:
            y += sy
            if err >= n:
                err -= n
                x += sx
    return out


@pytest.mark.parametrize("seed", range(5))
def test_line_cells_match_a_textbook_bresenham(seed):
    rng = np.random.default_rng(seed)
    for x0, y0, x1, y1 in rng.integers(-20, 20, size=(200, 4)):
        line = outline_and_fill(np.array([[x0, y0], [x1, y1]], np.int64), 1, False)
        assert list(map(tuple, line.tolist())) == reference_line(x0, y0, x1, y1)


def test_an_axis_aligned_footprint_covers_its_whole_cell_block():
    cm = Costmap(np.zeros((40, 40), np.uint8), (0.0, 0.0), RES)
    cells = footprint_cells_upstream(cm, (1.0, 1.0, 0.0), SQUARE)
    block = {(x, y) for x in range(15, 25) for y in range(15, 25)}   # 0.79..1.21 m
    assert set(map(tuple, cells)) == block


def test_a_rotated_footprint_covers_every_cell_centre_inside_it():
    cm = Costmap(np.zeros((40, 40), np.uint8), (0.0, 0.0), RES)
    th = 0.6
    cells = set(map(tuple, footprint_cells_upstream(cm, (1.0, 1.0, th), SQUARE)))
    c, s = np.cos(-th), np.sin(-th)
    for mx in range(40):
        for my in range(40):
            px, py = (mx + 0.5) * RES - 1.0, (my + 0.5) * RES - 1.0
            bx, by = px * c - py * s, px * s + py * c       # into the robot frame
            if abs(bx) < 0.2 and abs(by) < 0.2:
                assert (mx, my) in cells


def test_off_map_vertex_ends_the_outline_unfilled():
    cm = Costmap(np.zeros((40, 40), np.uint8), (0.0, 0.0), RES)
    assert len(footprint_cells_upstream(cm, (0.1, 1.0, 0.0), SQUARE)) == 0   # vertex 0 off


def test_rotation_memory_refuses_the_other_side_after_two_turns_one_way():
    upstream = Oscillation().after(0.0, -0.5, (0.0, 0.0), True)
    assert upstream.allows(0.5) and upstream.allows(-0.5)
    upstream = upstream.after(0.0, -0.5, (0.0, 0.0), True)
    assert upstream.allows(-0.5) and not upstream.allows(0.5)
    legacy = Oscillation().after(0.0, -0.5, (0.0, 0.0)).after(0.0, 0.5, (0.0, 0.0))
    assert not legacy.allows(-0.5) and legacy.allows(0.5)


def test_local_goal_is_the_last_point_and_goal_grid_exempts_nothing():
    costs = np.zeros((80, 80), np.uint8)
    costs[30:50, 50:52] = INSCRIBED              # a wall the plan crosses 2 m from its start
    costs[38:42, 18:22] = INSCRIBED              # under the robot
    cm = Costmap(costs, (0.0, 0.0), RES)
    xs = np.linspace(0.5, 3.5, 61)
    plan = np.column_stack([xs, np.full_like(xs, 2.0), np.zeros_like(xs)])
    pose = (1.0, 2.0, 0.0)
    legacy, upstream = DistanceGrids(), DistanceGrids(upstream=True)
    for grids in (legacy, upstream):
        grids.update(cm, pose, plan, SQUARE, radius=200)
    assert legacy.goal[40, 49] == 0.0            # goal: the last free point before the band
    assert upstream.goal[40, 70] == 0.0          # goal: the plan's last point
    obstacle = costs.size                        # target_distance's value for an obstacle
    assert legacy.goal[40, 20] < obstacle        # the robot's cells reached by the goal BFS
    assert upstream.goal[40, 20] >= obstacle     # ... not without the exemption
    assert upstream.goal[40, 10] < obstacle      # (the goal BFS goes round the wall)
    assert upstream.path[40, 20] < obstacle      # the path grid keeps the exemption


def test_float_pose_rounds_what_find_best_path_plans_from():
    cfg = TrajectoryPlannerConfig(upstream_rules=True)
    tp = TrajectoryPlanner(cfg, SQUARE, 0.05, RES)
    cm = Costmap(np.zeros((60, 60), np.uint8), (0.0, 0.0), RES)
    xs = np.linspace(1.0, 2.9, 39)
    tp.update_plan(np.column_stack([xs, np.full_like(xs, 1.5), np.zeros_like(xs)]))
    pose = (1.0 + 1e-9, 1.5, 0.0)
    best = tp.find_best_path(cm, pose, (0.1, 0.0, 0.0))
    assert best.points[0][0] == float(np.float32(pose[0])) != pose[0]


def test_the_option_is_hashed_only_when_on():
    """Off, the hash is that of the records before the option (the shipped models' campaigns
    check that, tests/learn/test_shipped_model_campaigns.py); on, it differs."""
    cfg = TrajectoryPlannerConfig()
    assert config_hash(cfg) != config_hash(dataclasses.replace(cfg, upstream_rules=True))


def reference_fill(outline):
    """getFillCells as upstream writes it, slowly: its in-place exchange sort (swap neighbours
    whose x is strictly greater, step back after each swap), then per column every cell from
    the lowest outline cell up to the highest."""
    cells = list(outline)
    i = 0
    while i < len(cells) - 1:
        if cells[i][0] > cells[i + 1][0]:
            cells[i], cells[i + 1] = cells[i + 1], cells[i]
            i = max(i - 1, 0)
        else:
            i += 1
    filled, i = list(cells), 0
    for x in range(cells[0][0], cells[-1][0] + 1):
        if i >= len(cells) - 1:
            break
        column = [cells[i], cells[i + 1]]
        i += 2
        while i < len(cells) and cells[i][0] == x:
            column.append(cells[i])
            i += 1
        ys = [c[1] for c in column]
        filled += [(x, y) for y in range(min(ys), max(ys))]
    return filled


@pytest.mark.parametrize("seed", range(5))
def test_outline_and_fill_equals_upstreams_exchange_sort_and_fill(seed):
    """Random polygons (columns met in every order, degenerate edges too): the textbook outline
    filled by the reference gives the same list, order and duplicates included."""
    rng = np.random.default_rng(seed)
    for _ in range(200):
        corners = rng.integers(0, 30, size=(rng.integers(3, 7), 2))
        outline = [c for k, a in enumerate(corners)
                   for c in reference_line(*a, *corners[(k + 1) % len(corners)])]
        cells = outline_and_fill(corners.astype(np.int64), len(corners), True)
        assert list(map(tuple, cells.tolist())) == reference_fill(outline)
