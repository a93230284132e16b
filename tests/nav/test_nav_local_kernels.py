"""The local planner's per-cycle kernels against slow references (the numpy and Python forms
they replace): the plan's cells and local goal, the forward samples and the cheapest pick."""
from __future__ import annotations

import numpy as np
import pytest

from slam_predict.nav.costmap import INSCRIBED, LETHAL, NO_INFORMATION, Costmap
from slam_predict.nav.map_grid import adjust_plan_resolution, path_and_goal_cells
from slam_predict.nav.rollout import first_cheapest, forward_samples


def ref_adjust(plan_xy, resolution):
    """MapGrid::adjustPlanResolution, vectorised with numpy."""
    plan_xy = np.asarray(plan_xy, dtype=float).reshape(-1, 2)
    if len(plan_xy) < 2:
        return plan_xy
    seg = np.diff(plan_xy, axis=0)
    length = np.hypot(seg[:, 0], seg[:, 1])
    steps = np.where(length > resolution, np.ceil(length / resolution), 1).astype(int)
    seg_index = np.repeat(np.arange(len(seg)), steps)
    offsets = np.arange(len(seg_index)) - np.repeat(np.cumsum(steps) - steps, steps)
    frac = offsets / steps[seg_index]
    points = plan_xy[seg_index] + frac[:, None] * seg[seg_index]
    return np.vstack([points, plan_xy[-1:]])


def ref_path_and_goal(costmap, plan):
    """setTargetCells' run and setLocalGoal's cell, with numpy masks."""
    empty = np.empty((0, 2), np.int64)
    if len(plan) == 0:
        return empty, empty
    pts = ref_adjust(np.asarray(plan, dtype=float)[:, :2], costmap.resolution)
    ox, oy = costmap.origin
    inside = (pts[:, 0] >= ox) & (pts[:, 1] >= oy)
    mx = np.zeros(len(pts), np.int64)
    my = np.zeros(len(pts), np.int64)
    mx[inside] = ((pts[inside, 0] - ox) / costmap.resolution).astype(np.int64)
    my[inside] = ((pts[inside, 1] - oy) / costmap.resolution).astype(np.int64)
    inside &= (mx < costmap.size_x) & (my < costmap.size_y)
    ok = np.zeros(len(pts), bool)
    ok[inside] = costmap.costs[my[inside], mx[inside]] != NO_INFORMATION
    if not ok.any():
        return empty, empty
    first = int(np.argmax(ok))
    rest = ok[first:]
    stop = first + (len(rest) if rest.all() else int(np.argmin(rest)))
    run = np.arange(first, stop)
    path = np.stack([mx[run], my[run]], axis=1)
    away = np.maximum.accumulate(np.hypot(*(pts - pts[0]).T) ** 2 > 1.0)[run]
    blocked = costmap.costs[my[run], mx[run]] >= INSCRIBED
    ends = np.nonzero(away[1:] & blocked[1:] & ~blocked[:-1])[0]
    k = ends[0] if len(ends) else len(run) - 1
    return path, path[k:k + 1]


def random_scene(rng):
    """A 60 × 60 costmap with blobs of every special cost and a wandering plan (n, 3) that may
    start or leave off the map."""
    costs = rng.choice(np.array([0, 0, 0, 0, 50, INSCRIBED, LETHAL, NO_INFORMATION], np.uint8),
                       size=(60, 60))
    costs = np.repeat(np.repeat(costs[::6, ::6], 6, axis=0), 6, axis=1)
    n = int(rng.integers(0, 30))
    xy = np.cumsum(rng.normal(0.0, 0.15, (n, 2)), axis=0) + rng.uniform(-0.3, 3.3, 2)
    if n > 3 and rng.random() < 0.3:
        xy[2] = xy[1]                              # a repeated point (a zero-length segment)
    plan = np.column_stack([xy, rng.uniform(-3, 3, n)])
    return Costmap(costs, (0.0, 0.0), 0.05), plan


@pytest.mark.parametrize("seed", range(300))
def test_path_and_goal_cells_match_the_reference(seed):
    cm, plan = random_scene(np.random.default_rng(seed))
    path, goal = path_and_goal_cells(cm, plan)
    ref_path, ref_goal = ref_path_and_goal(cm, plan)
    assert np.array_equal(path, ref_path) and np.array_equal(goal, ref_goal)
    assert path.dtype == ref_path.dtype and goal.shape == ref_goal.shape


@pytest.mark.parametrize("seed", range(50))
def test_adjust_plan_resolution_matches_the_reference_bit_for_bit(seed):
    rng = np.random.default_rng(seed)
    xy = np.cumsum(rng.normal(0.0, 0.2, (int(rng.integers(0, 20)), 2)), axis=0)
    assert np.array_equal(adjust_plan_resolution(xy, 0.02), ref_adjust(xy, 0.02))


def ref_forward_samples(min_vx, dvx, min_vth, dvth, nvx, nvth):
    """createTrajectories' forward samples, in a Python list."""
    out = []
    vx = min_vx
    for _ in range(nvx):
        out.append((vx, 0.0))
        vth = min_vth
        for _ in range(nvth - 1):
            out.append((vx, vth))
            vth += dvth
        vx += dvx
    return np.array(out, dtype=float)


@pytest.mark.parametrize("seed", range(30))
def test_forward_samples_and_cheapest_pick_match_the_reference(seed):
    rng = np.random.default_rng(seed)
    args = (rng.uniform(0, 0.3), rng.uniform(0, 0.1), rng.uniform(-1, 0), rng.uniform(0, 0.1),
            int(rng.integers(1, 12)), int(rng.integers(1, 22)))
    samples = forward_samples(*args)
    assert np.array_equal(samples, ref_forward_samples(*args))
    costs = rng.choice(np.array([-2.0, -1.0, 0.0, 3.5, 3.5, 7.0]), size=len(samples))
    legal = [k for k in range(len(costs)) if costs[k] >= 0]
    expected = min(legal, key=lambda k: (costs[k], k)) if legal else -1
    assert first_cheapest(costs) == expected
