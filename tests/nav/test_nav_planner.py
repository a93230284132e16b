"""Global planner against a slow reference Dijkstra on random mazes; unknown space, tolerance."""
from __future__ import annotations

import heapq
import math

import numpy as np
import pytest

from slam_predict.nav.config import MoveBaseConfig, NavfnConfig
from slam_predict.nav.costmap import (
    FREE,
    INSCRIBED,
    LETHAL,
    NO_INFORMATION,
    Costmap,
    InflationLayer,
)
from slam_predict.nav.planner import GlobalPlanner, navfn_cell_costs

RES = 0.05


def reference_dijkstra(cell_cost: np.ndarray, start, goal) -> float:
    """Cheapest 8-connected cost start -> goal; entering cell v costs step·cost[v]."""
    ny, nx = cell_cost.shape
    best = {start: 0.0}
    heap = [(0.0, start)]
    done = set()
    while heap:
        d, (x, y) = heapq.heappop(heap)
        if (x, y) in done:
            continue
        done.add((x, y))
        if (x, y) == goal:
            return d
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                if dx == dy == 0:
                    continue
                vx, vy = x + dx, y + dy
                if not (0 <= vx < nx and 0 <= vy < ny) or not math.isfinite(cell_cost[vy, vx]):
                    continue
                nd = d + math.hypot(dx, dy) * cell_cost[vy, vx]
                if nd < best.get((vx, vy), math.inf):
                    best[(vx, vy)] = nd
                    heapq.heappush(heap, (nd, (vx, vy)))
    return math.inf


def dfs_maze(rng, cells=8, scale=4) -> np.ndarray:
    """A perfect maze (random DFS) with corridors ``scale`` - 1 cells wide; LETHAL walls."""
    size = cells * scale + 1
    grid = np.full((size, size), LETHAL, np.uint8)
    seen = np.zeros((cells, cells), bool)
    stack = [(0, 0)]
    seen[0, 0] = True
    while stack:
        cx, cy = stack[-1]
        grid[cy * scale + 1:(cy + 1) * scale, cx * scale + 1:(cx + 1) * scale] = FREE
        options = [(cx + dx, cy + dy) for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1))
                   if 0 <= cx + dx < cells and 0 <= cy + dy < cells and not seen[cy + dy, cx + dx]]
        if not options:
            stack.pop()
            continue
        nx_, ny_ = options[rng.integers(len(options))]
        seen[ny_, nx_] = True
        x0, x1 = sorted((cx, nx_))
        y0, y1 = sorted((cy, ny_))
        grid[y0 * scale + 1:(y1 + 1) * scale, x0 * scale + 1:(x1 + 1) * scale] = FREE
        stack.append((nx_, ny_))
    return grid


def random_blocks(rng, shape=(45, 50), p=0.3) -> np.ndarray:
    grid = np.where(rng.random(shape) < p, LETHAL, FREE).astype(np.uint8)
    return grid


def planner(**navfn) -> GlobalPlanner:
    return GlobalPlanner(MoveBaseConfig(NavfnROS=NavfnConfig(**navfn)))


def world(cell) -> tuple:
    return ((cell[0] + 0.5) * RES, (cell[1] + 0.5) * RES, 0.0)


def free_cells(costs: np.ndarray):
    ys, xs = np.nonzero(costs[1:-1, 1:-1] < INSCRIBED)
    return list(zip(xs + 1, ys + 1, strict=False))


def path_cells(plan, costmap):
    return np.array([costmap.world_to_map(x, y) for x, y, _ in plan.poses])


def check_legal(plan, costmap):
    cells = path_cells(plan, costmap)
    steps = np.abs(np.diff(cells, axis=0))
    assert steps.max() <= 1, "path jumps over cells"
    values = costmap.costs[cells[1:, 1], cells[1:, 0]]
    assert np.all(values < INSCRIBED), "path crosses lethal/inscribed cells"


@pytest.mark.parametrize("seed", range(8))
def test_length_within_5_percent_of_8_connected_dijkstra(seed):
    rng = np.random.default_rng(seed)
    grid = dfs_maze(rng) if seed % 2 else random_blocks(rng)
    costmap = Costmap(grid, (0.0, 0.0), RES)
    cells = free_cells(grid)
    for _ in range(3):
        s = cells[rng.integers(len(cells))]
        g = cells[rng.integers(len(cells))]
        unit = np.where(grid < INSCRIBED, 1.0, np.inf)
        unit[[0, -1], :] = np.inf
        unit[:, [0, -1]] = np.inf
        ref = reference_dijkstra(unit, s, g)
        plan = planner().make_plan(costmap, world(s), world(g))
        if math.isinf(ref):
            assert plan is None
            continue
        assert plan is not None and plan.reaches_goal
        check_legal(plan, costmap)
        assert plan.length <= 1.05 * ref * RES + 1e-9


@pytest.mark.parametrize("kind", ["navfn/NavfnROS", "global_planner/GlobalPlanner"])
@pytest.mark.parametrize("seed", range(5))
def test_cost_within_1_percent_of_optimum(seed, kind):
    rng = np.random.default_rng(100 + seed)
    grid = dfs_maze(rng, cells=6, scale=6) if seed % 2 else random_blocks(rng, (40, 42), 0.15)
    InflationLayer(0.2, 5.0, 0.06, RES).apply(grid)
    grid[(grid < INSCRIBED) & (rng.random(grid.shape) < 0.2)] = 120  # extra cost patches
    costmap = Costmap(grid, (0.0, 0.0), RES)
    gp = GlobalPlanner(MoveBaseConfig(base_global_planner=kind))
    weights = gp.cell_costs(grid)
    cells = free_cells(grid)
    for _ in range(3):
        s = cells[rng.integers(len(cells))]
        g = cells[rng.integers(len(cells))]
        ref = reference_dijkstra(weights, s, g)
        plan = gp.make_plan(costmap, world(s), world(g))
        if math.isinf(ref):
            assert plan is None
            continue
        check_legal(plan, costmap)
        assert plan.cost <= 1.01 * ref + 1e-9
        cells_on = path_cells(plan, costmap)
        recomputed = sum(math.hypot(*(b - a)) * weights[b[1], b[0]]
                         for a, b in zip(cells_on[:-1], cells_on[1:], strict=False))
        assert recomputed == pytest.approx(plan.cost)


def test_frontier_goal_in_unknown_space_is_reachable():
    grid = np.full((40, 60), NO_INFORMATION, np.uint8)
    grid[5:35, 5:30] = FREE
    costmap = Costmap(grid, (0.0, 0.0), RES)
    goal = world((45, 20))
    plan = planner(allow_unknown=True).make_plan(costmap, world((10, 20)), goal)
    assert plan is not None and plan.reaches_goal
    assert plan.poses[-1, 0] == pytest.approx(goal[0])
    assert planner(allow_unknown=False).make_plan(costmap, world((10, 20)), goal) is None


def test_blocked_goal_uses_tolerance_nearest_reachable_cell():
    grid = np.zeros((40, 40), np.uint8)
    grid[:, 20:23] = LETHAL          # a wall; the goal is inside it
    costmap = Costmap(grid, (0.0, 0.0), RES)
    goal = world((21, 10))
    assert planner().make_plan(costmap, world((5, 10)), goal) is None
    plan = planner(default_tolerance=0.2).make_plan(costmap, world((5, 10)), goal)
    assert plan is not None and not plan.reaches_goal
    end = costmap.world_to_map(*plan.poses[-1, :2])
    assert end == (19, 10)           # the nearest reachable cell to the goal
    check_legal(plan, costmap)


def test_unreachable_goal_fails_and_start_cell_is_always_usable():
    grid = np.zeros((30, 30), np.uint8)
    grid[10:20, 10] = grid[10:20, 19] = LETHAL
    grid[10, 10:20] = grid[19, 10:20] = LETHAL
    costmap = Costmap(grid, (0.0, 0.0), RES)
    assert planner().make_plan(costmap, world((3, 3)), world((15, 15))) is None
    grid2 = np.zeros((30, 30), np.uint8)
    grid2[5, 5] = INSCRIBED                      # robot standing on an inscribed cell
    plan = planner().make_plan(Costmap(grid2, (0.0, 0.0), RES), world((5, 5)), world((20, 20)))
    assert plan is not None


def test_search_is_limited_to_the_known_region():
    grid = np.full((2000, 2000), NO_INFORMATION, np.uint8)
    grid[1000:1040, 1000:1060] = FREE
    costmap = Costmap(grid, (-50.0, -50.0), RES)
    gp = planner()
    x0, y0, x1, y1 = gp._search_box(costmap, (1010, 1010), (1050, 1030), 0)
    assert (x1 - x0) * (y1 - y0) < 200 * 200
    plan = gp.make_plan(costmap, (0.52, 0.52, 0.0), (2.52, 1.52, 0.0))
    assert plan is not None and plan.reaches_goal


def test_navfn_cost_translation():
    costs = np.array([[0, 100, 252, 253, 254, 255]] * 3, np.uint8)
    out = navfn_cell_costs(costs, allow_unknown=True)[1]
    assert np.isinf(out[0]) and np.isinf(out[-1])   # the border is an obstacle
    assert out[1] == pytest.approx(130.0)
    assert out[2] == pytest.approx(251.6)
    assert np.isinf(out[3]) and np.isinf(out[4])


@pytest.mark.parametrize("allow_unknown", [False, True])
def test_navfn_costs_of_every_costmap_value_follow_the_rule(allow_unknown):
    """Cell by cell: 50 + 0.8 c below INSCRIBED, 253 for unknown when allowed, else blocked."""
    costs = np.arange(256, dtype=np.uint8).reshape(16, 16)
    padded = np.pad(costs, 1)
    out = navfn_cell_costs(padded, allow_unknown)[1:-1, 1:-1]
    for c, got in zip(costs.ravel(), out.ravel(), strict=True):
        if c < INSCRIBED:
            assert got == 50.0 + 0.8 * float(c)
        elif c == NO_INFORMATION and allow_unknown:
            assert got == 253.0
        else:
            assert got == np.inf


# --------------------------------------------------------------------- start escape (issue #5)
def pinned_costmap():
    """A 3 m x 2 m room at 0.05 m, its south wall 3 cells thick, inflated for the project's 0.42 m
    footprint (inscribed radius 0.21 m): rows 3..7 are INSCRIBED."""
    grid = np.zeros((40, 60), np.uint8)
    grid[:3, :] = LETHAL
    InflationLayer(2.25, 7.5, 0.21, RES).apply(grid)
    return Costmap(grid, (0.0, 0.0), RES)


def test_robot_pinned_in_the_inscribed_band_still_gets_a_plan_out():
    """school_6000: a robot backed against a wall (centre 0.15 m from it, stalled) had no plan to
    anywhere (navfn expands only through cells < INSCRIBED), every goal ABORTED."""
    costmap = pinned_costmap()
    start = (1.52, 0.27, 0.0)                       # cell (30, 5): INSCRIBED, as its neighbours
    s = costmap.world_to_map(*start[:2])
    assert np.all(costmap.costs[s[1] - 1:s[1] + 2, s[0] - 1:s[0] + 2] == INSCRIBED)
    goal = (1.52, 1.5, math.pi / 2)
    plan = planner().make_plan(costmap, start, goal)
    assert plan is not None and plan.reaches_goal
    cells = path_cells(plan, costmap)
    values = costmap.costs[cells[:, 1], cells[:, 0]]
    assert np.all(values < LETHAL)
    band = values >= INSCRIBED                     # the inscribed cells are only the way out
    assert band[0] and not band[-1]
    assert np.all(np.diff(band.astype(int)) <= 0)
    off = np.hypot(cells[band, 0] - s[0], cells[band, 1] - s[1]) * RES
    assert off.max() <= 0.30                        # within the circumscribed radius 0.297 m
    # a plan from outside the band never enters it; disabled escape = navfn's failure
    assert planner().make_plan(costmap, (1.52, 0.6, 0.0), goal) is not None
    gp = GlobalPlanner(MoveBaseConfig(), escape_radius=0.0)
    assert gp.make_plan(costmap, start, goal) is None


def test_start_escape_does_not_cross_walls_or_long_inscribed_corridors():
    """Only INSCRIBED cells near the start open up: a goal behind a wall, or through a corridor
    narrower than the robot further away, stays unreachable."""
    grid = np.zeros((40, 80), np.uint8)
    grid[:3, :] = LETHAL
    grid[:, 40:43] = LETHAL                         # a full wall at x = 2.0 m
    InflationLayer(2.25, 7.5, 0.21, RES).apply(grid)
    costmap = Costmap(grid, (0.0, 0.0), RES)
    start = (1.02, 0.27, 0.0)
    assert planner().make_plan(costmap, start, (3.0, 1.0, 0.0)) is None
    grid2 = np.full((40, 80), LETHAL, np.uint8)
    grid2[3:37, 3:30] = FREE                        # a room ...
    grid2[18:22, 30:77] = FREE                      # ... and a 0.2 m wide corridor off it
    InflationLayer(2.25, 7.5, 0.21, RES).apply(grid2)
    corridor = Costmap(grid2, (0.0, 0.0), RES)
    plan = planner().make_plan(corridor, (0.27, 1.0, 0.0), (3.5, 1.0, 0.0))
    assert plan is None


@pytest.mark.parametrize("seed", range(3))
def test_reused_search_work_gives_the_fresh_searches_results(seed):
    """One SearchWork over many searches of several sizes (as a planner keeps it) returns the
    paths and costs of searches each given new, cleared arrays."""
    from slam_predict.nav.search import SearchWork
    from slam_predict.nav.search import search_costs as _search

    rng = np.random.default_rng(seed)
    kept = SearchWork()
    for _ in range(12):
        ny, nx = rng.integers(8, 40, size=2)
        cost = rng.choice([50.0, 80.0, 130.0, np.inf], size=(ny, nx), p=[0.5, 0.2, 0.1, 0.2])
        s = random_cell(rng, cost)
        g = random_cell(rng, cost)
        tol = int(rng.integers(0, 3))
        ours = _search(cost, s, g, tol, kept)
        fresh = _search(cost, s, g, tol, SearchWork())
        assert np.array_equal(ours[0], fresh[0]) and ours[1] == fresh[1]
        if len(ours[0]) and ours[0][-1].tolist() == list(g):
            assert ours[1] == pytest.approx(reference_dijkstra(cost, s, g), rel=1e-9)
    assert kept.stamp == 12


class ReferenceHeap:
    """The kernel's binary min-heap in plain Python (same sift rules, so the same pop order on
    equal keys)."""

    def __init__(self):
        self.items: list[list] = []

    def push(self, key: float, val: int) -> None:
        items, i = self.items, len(self.items)
        items.append([key, val])
        while i > 0 and items[(i - 1) >> 1][0] > items[i][0]:
            items[(i - 1) >> 1], items[i] = items[i], items[(i - 1) >> 1]
            i = (i - 1) >> 1

    def pop(self) -> tuple[float, int]:
        items = self.items
        top, last = items[0], items.pop()
        if items:
            items[0], i = last, 0
            while 2 * i + 1 < len(items):
                small = 2 * i + 1
                if small + 1 < len(items) and items[small + 1][0] < items[small][0]:
                    small += 1
                if items[i][0] <= items[small][0]:
                    break
                items[small], items[i] = items[i], items[small]
                i = small
        return top[0], top[1]


@pytest.mark.parametrize("seed", range(4))
def test_kernel_heap_pops_in_the_reference_heaps_order_ties_included(seed):
    """The kernel's heap (hole down to a leaf, then the last entry up) pops the same (key,
    value) sequence as the plain sift-down heap over random pushes and pops with few keys."""
    from slam_predict.nav.kernels import _heap_pop, _heap_push

    rng = np.random.default_rng(seed)
    keys, vals, size = np.empty(2000), np.empty(2000, np.int32), 0
    ref = ReferenceHeap()
    for step in range(3000):
        if size and rng.random() < 0.45:
            key, val, size = _heap_pop(keys, vals, size)
            assert (key, val) == ref.pop()
        elif size < 2000:
            key = float(rng.integers(0, 6))
            size = _heap_push(keys, vals, size, key, step)
            ref.push(key, step)
    while size:
        key, val, size = _heap_pop(keys, vals, size)
        assert (key, val) == ref.pop()


def reference_window_search(cost, start, goal, tol, weight):
    """grid_search's rules in plain Python with fresh dicts: A* from start, stop when the goal
    is settled or every traversable window cell is; end = nearest settled window cell (ties:
    row-major first); returns (path [(x, y)...], cost)."""
    ny, nx = cost.shape
    (sx, sy), (gx, gy) = start, goal
    window = [(x, y) for y in range(max(gy - tol, 0), min(gy + tol, ny - 1) + 1)
              for x in range(max(gx - tol, 0), min(gx + tol, nx - 1) + 1)]
    to_settle = sum(1 for x, y in window if np.isfinite(cost[y, x]) or (x, y) == start)
    g, parent, done, heap = {start: 0.0}, {}, set(), ReferenceHeap()
    heap.push(weight * math.hypot(sx - gx, sy - gy), start)
    while heap.items and to_settle > 0:
        _, u = heap.pop()
        if u in done:
            continue
        done.add(u)
        if abs(u[0] - gx) <= tol and abs(u[1] - gy) <= tol:
            to_settle -= 1
            if u == goal:
                break
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                v = (u[0] + dx, u[1] + dy)
                if (dx, dy) == (0, 0) or not (0 <= v[0] < nx and 0 <= v[1] < ny) or v in done:
                    continue
                if not np.isfinite(cost[v[1], v[0]]):
                    continue
                gv = g[u] + (math.sqrt(2.0) if dx and dy else 1.0) * cost[v[1], v[0]]
                if v not in g or gv < g[v]:
                    g[v], parent[v] = gv, u
                    heap.push(gv + weight * math.hypot(v[0] - gx, v[1] - gy), v)
    settled = [c for c in window if c in done]
    if goal not in done and not settled:
        return [], math.inf
    end = goal if goal in done else min(settled, key=lambda c: (c[0] - gx) ** 2 + (c[1] - gy) ** 2)
    path = [end]
    while path[-1] != start:
        path.append(parent[path[-1]])
    return path[::-1], g[end]


def random_costs(rng, size_range, shares) -> np.ndarray:
    """A random navfn cost grid (50, 100 or lethal ∞ with these shares), sides in size_range."""
    ny, nx = rng.integers(*size_range, size=2)
    return rng.choice([50.0, 100.0, np.inf], size=(ny, nx), p=shares)


def random_cell(rng, cost: np.ndarray) -> tuple[int, int]:
    """A random cell (x, y) of ``cost``, x drawn first."""
    ny, nx = cost.shape
    return int(rng.integers(nx)), int(rng.integers(ny))


def reference_weight(cost: np.ndarray) -> float:
    """The planner's heuristic weight on ``cost`` (capped at 1 as nav/planner.py takes it)."""
    return min(float(np.min(cost[np.isfinite(cost)], initial=1.0)), 50.0)


def assert_same_search(found, expected) -> None:
    """Same path cells and the same total cost (both infinite counts as the same)."""
    (path, total), (ref_path, ref_total) = found, expected
    assert [tuple(c) for c in path.tolist()] == ref_path
    assert total == ref_total or (math.isinf(total) and math.isinf(ref_total))


@pytest.mark.parametrize("seed", range(4))
def test_search_equals_a_plain_python_port_ties_included(seed):
    """Path cells and cost equal the plain-Python port's on random costmaps with few distinct
    costs (many equal keys: the pop order decides among equally cheap paths)."""
    from slam_predict.nav.search import SearchWork
    from slam_predict.nav.search import search_costs as _search

    rng = np.random.default_rng(100 + seed)
    work = SearchWork()
    for _ in range(15):
        cost = random_costs(rng, (6, 30), [0.6, 0.2, 0.2])
        s = random_cell(rng, cost)
        g = random_cell(rng, cost)
        tol = int(rng.integers(0, 3))
        expected = reference_window_search(cost, s, g, tol, reference_weight(cost))
        assert_same_search(_search(cost, s, g, tol, work), expected)


def test_a_repeated_request_gets_the_searched_plan_and_a_changed_costmap_a_new_search():
    """The last request's plan is given back only for the same start cell, goal, tolerance and
    costs; it equals a fresh planner's plan, and a change of one cell means a new search."""
    rng = np.random.default_rng(7)
    grid = np.where(dfs_maze(rng) == 0, FREE, LETHAL).astype(np.uint8)
    costmap = Costmap(grid, (0.0, 0.0), RES)
    cells = free_cells(grid)
    start, goal = world(cells[0]), world(cells[-1])[:2] + (0.5,)
    kept = planner()
    first = kept.make_plan(costmap, start, goal)
    stamp = kept.work.stamp
    nudged = (start[0] + 0.2 * RES, start[1], 1.0)           # same cell, other heading
    again = kept.make_plan(costmap, nudged, goal)
    assert kept.work.stamp == stamp                           # no search
    assert np.array_equal(again.poses, first.poses) and again.cost == first.cost
    again.poses[0, 0] = -1.0                                  # a caller's edit stays its own
    assert kept.make_plan(costmap, start, goal).poses[0, 0] == first.poses[0, 0]
    changed = Costmap(grid.copy(), (0.0, 0.0), RES)
    path = path_cells(first, costmap)
    changed.costs[path[len(path) // 2][1], path[len(path) // 2][0]] = LETHAL
    replanned = kept.make_plan(changed, start, goal)
    assert kept.work.stamp == stamp + 1
    fresh = planner().make_plan(changed, start, goal)
    assert (replanned is None) == (fresh is None)
    if fresh is not None:
        assert np.array_equal(replanned.poses, fresh.poses)
    other_goal = kept.make_plan(changed, start, world(cells[len(cells) // 2]))
    assert kept.work.stamp == stamp + 2 and other_goal is not None


@pytest.mark.parametrize("seed", range(6))
def test_a_paused_search_ends_as_the_plain_search(seed):
    """Searches paused after a few cells and resumed knowing which window cells no path
    reaches end with the plain-Python port's path and cost, also when walls cut the goal
    window off (where the port empties its queue)."""
    from slam_predict.nav.search import SearchWork, search_costs

    rng = np.random.default_rng(300 + seed)
    work = SearchWork()
    for _ in range(12):
        cost = random_costs(rng, (10, 35), [0.55, 0.2, 0.25])
        ny, nx = cost.shape
        g = random_cell(rng, cost)
        wall = int(rng.integers(0, nx))
        cost[:, wall] = np.inf                     # often splits the goal window off
        s = random_cell(rng, cost)
        tol = int(rng.integers(0, 4))
        expected = reference_window_search(cost, s, g, tol, reference_weight(cost))
        for pause in (0, 1, 7, 40, None):
            assert_same_search(search_costs(cost, s, g, tol, work, pause), expected)
