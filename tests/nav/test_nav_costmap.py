"""Costmap layers against slow references: a literal port of costmap_2d's inflation, an exact
distance transform, the static translation table and obstacle marking/clearing."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from scipy import ndimage

from slam_predict.nav.config import CostmapConfig
from slam_predict.nav.costmap import (
    FREE,
    INSCRIBED,
    LETHAL,
    NO_INFORMATION,
    InflationLayer,
    footprint_radii,
    inscribed_radius,
    make_footprint,
    static_costs,
)
from slam_predict.nav.layered import LayeredCostmap, changed_box


def reference_inflate(master: np.ndarray, layer: InflationLayer) -> np.ndarray:
    """InflationLayer::updateCosts over the whole map, written out with Python containers:
    a dict of distance bins visited in increasing order (a bin created below the current one is
    never visited, as with std::map iteration), FIFO inside a bin."""
    out = master.copy()
    ny, nx = out.shape
    seen = np.zeros(out.shape, bool)
    radius = layer.cell_radius
    bins = {0.0: [(i, j, i, j) for j in range(ny) for i in range(nx) if master[j, i] == LETHAL]}
    current = None
    while True:
        later = [k for k in bins if current is None or k > current]
        if not later:
            return out
        current = min(later)
        queue = bins[current]
        k = 0
        while k < len(queue):
            mx, my, sx, sy = queue[k]
            k += 1
            if seen[my, mx]:
                continue
            seen[my, mx] = True
            cost = int(layer.cost_cache[abs(mx - sx), abs(my - sy)])
            old = int(out[my, mx])
            if old == NO_INFORMATION:
                out[my, mx] = cost if cost >= INSCRIBED else old
            else:
                out[my, mx] = max(old, cost)
            for qx, qy in ((mx - 1, my), (mx, my - 1), (mx + 1, my), (mx, my + 1)):
                if 0 <= qx < nx and 0 <= qy < ny and not seen[qy, qx]:
                    d = float(layer.dist_cache[abs(qx - sx), abs(qy - sy)])
                    if d <= radius:
                        bins.setdefault(d, []).append((qx, qy, sx, sy))


def random_grid(rng, shape, p_lethal=0.01, p_unknown=0.0):
    grid = np.zeros(shape, np.uint8)
    grid[rng.random(shape) < p_unknown] = NO_INFORMATION
    grid[rng.random(shape) < p_lethal] = LETHAL
    return grid


def test_cost_function_values():
    layer = InflationLayer(0.55, 10.0, 0.21, 0.05)
    assert layer.cell_radius == 11
    assert layer.compute_cost(0) == LETHAL
    assert layer.compute_cost(4) == INSCRIBED  # 0.20 m <= 0.21 m
    assert layer.compute_cost(5) == int(252 * math.exp(-10.0 * (0.25 - 0.21)))
    assert layer.compute_cost(math.hypot(3, 4)) == layer.compute_cost(5.0)


@pytest.mark.parametrize("radius,factor", [(0.45, 7.5), (1.0, 15.0)])
@pytest.mark.parametrize("seed", range(4))
def test_inflation_matches_literal_costmap_2d_port(seed, radius, factor):
    """(1.0 m, 15/m): costs reach 0 at 0.58 m, so the kernel's early stop is exercised."""
    rng = np.random.default_rng(seed)
    layer = InflationLayer(radius, factor, 0.21, 0.05)
    grid = random_grid(rng, (31, 37), 0.02, 0.1 if seed % 2 else 0.0)
    fast = grid.copy()
    layer.apply(fast)
    np.testing.assert_array_equal(fast, reference_inflate(grid, layer))


def test_inflation_close_to_exact_distance_transform():
    """The brushfire approximates the exact nearest-obstacle distance: almost every cell gets
    the cost of its true distance, and LETHAL/INSCRIBED classes never differ."""
    rng = np.random.default_rng(7)
    layer = InflationLayer(2.25, 7.5, 0.21, 0.05)
    grid = random_grid(rng, (120, 140), 0.005)
    fast = grid.copy()
    layer.apply(fast)
    dist = ndimage.distance_transform_edt(grid != LETHAL)
    exact = np.where(dist <= layer.cell_radius,
                     np.vectorize(layer.compute_cost)(dist), FREE).astype(np.uint8)
    assert np.mean(fast == exact) > 0.999
    assert np.array_equal(fast >= INSCRIBED, exact >= INSCRIBED)


def test_inflation_respects_unknown_rule():
    layer = InflationLayer(0.3, 10.0, 0.1, 0.05)
    grid = np.full((9, 9), NO_INFORMATION, np.uint8)
    grid[4, 4] = LETHAL
    layer.apply(grid)
    assert grid[4, 5] == INSCRIBED           # 0.05 m <= 0.1 m: overwrites unknown
    assert grid[4, 8] == NO_INFORMATION      # lower costs do not
    layer = InflationLayer(0.3, 10.0, 0.1, 0.05, inflate_unknown=True)
    grid = np.full((9, 9), NO_INFORMATION, np.uint8)
    grid[4, 4] = LETHAL
    layer.apply(grid)
    assert 0 < grid[4, 8] < INSCRIBED


def test_windowed_inflation_equals_full_inside_window():
    rng = np.random.default_rng(3)
    layer = InflationLayer(0.5, 5.0, 0.2, 0.05)
    grid = random_grid(rng, (60, 70), 0.01)
    full = grid.copy()
    layer.apply(full)
    part = grid.copy()
    layer.apply(part, (20, 15, 45, 40))
    np.testing.assert_array_equal(part[15:40, 20:45], full[15:40, 20:45])
    np.testing.assert_array_equal(part[:15], grid[:15])


def test_footprint_padding_and_radii():
    cfg = CostmapConfig(footprint=((-0.2, -0.2), (-0.2, 0.2), (0.2, 0.2), (0.2, -0.2)),
                        footprint_padding=0.01)
    fp = make_footprint(cfg)
    np.testing.assert_allclose(np.abs(fp), 0.21)
    inscribed, circumscribed = footprint_radii(fp)
    assert inscribed == pytest.approx(0.21)
    assert circumscribed == pytest.approx(0.21 * math.sqrt(2))
    circle = make_footprint(CostmapConfig(robot_radius=0.46, footprint_padding=0.0))
    assert len(circle) == 16
    assert footprint_radii(circle)[0] == pytest.approx(0.46 * math.cos(math.pi / 16))


@pytest.mark.parametrize("footprint, padding", [
    (((-0.2, -0.2), (-0.2, 0.2), (0.2, 0.2), (0.2, -0.2)), 0.01),   # config/costmap_common
    (((-0.3, -0.1), (-0.1, 0.25), (0.35, 0.15), (0.2, -0.2)), 0.02),
    ((), 0.0)])                                                         # 16-gon of robot_radius
def test_inscribed_radius_is_the_padded_polygons_distance_to_its_boundary(footprint, padding):
    """The robot centre's clearance: the distance from the centre to the nearest of many
    points sampled on the padded polygon's edges (the coverage's reachable-area rule)."""
    cfg = CostmapConfig(footprint=footprint, footprint_padding=padding, robot_radius=0.25)
    poly = make_footprint(cfg)
    s = np.linspace(0.0, 1.0, 20001)[:, None]
    edges = [a + s * (b - a) for a, b in zip(poly, np.roll(poly, -1, axis=0), strict=True)]
    nearest = np.min(np.hypot(*np.vstack(edges).T))
    assert inscribed_radius(cfg) == pytest.approx(nearest, abs=1e-5)


def test_static_translation_table():
    data = np.array([[-1, 0, 1, 50, 99, 100]], np.int8)
    tri = static_costs(data, CostmapConfig(track_unknown_space=True))
    assert tri.tolist() == [[NO_INFORMATION, 0, 0, 0, 0, LETHAL]]
    untracked = static_costs(data, CostmapConfig(track_unknown_space=False))
    assert untracked[0, 0] == FREE
    scaled = static_costs(data, CostmapConfig(track_unknown_space=True, trinary_costmap=False))
    assert scaled.tolist() == [[NO_INFORMATION, 0, 2, 127, 251, LETHAL]]


@pytest.mark.parametrize("cfg", [
    CostmapConfig(track_unknown_space=True), CostmapConfig(track_unknown_space=False),
    CostmapConfig(trinary_costmap=False), CostmapConfig(lethal_cost_threshold=65),
    CostmapConfig(unknown_cost_value=50, trinary_costmap=False)])
def test_static_table_of_an_int8_grid_equals_the_value_by_value_rule(cfg):
    """The int8 grid goes through a 256-entry table: every value as the int16 path maps it."""
    data = np.arange(-128, 128, dtype=np.int16).reshape(16, 16)
    assert np.array_equal(static_costs(data.astype(np.int8), cfg), static_costs(data, cfg))


def _grid(data, origin=(0.0, 0.0), res=0.05):
    return SimpleNamespace(data=np.asarray(data, np.int8), origin=origin, resolution=res)


def test_global_costmap_incremental_update_equals_fresh():
    rng = np.random.default_rng(5)
    cfg = CostmapConfig(static_map=True, track_unknown_space=True, inflation_radius=0.5,
                        cost_scaling_factor=5.0, observation_sources="",
                        footprint=((-0.2, -0.2), (-0.2, 0.2), (0.2, 0.2), (0.2, -0.2)))
    data = np.where(rng.random((80, 90)) < 0.01, 100, 0).astype(np.int8)
    data[:, :30] = -1
    cm = LayeredCostmap(cfg)
    cm.set_map(_grid(data, (1.0, -2.0)))
    cm.update((3.0, 0.0, 0.0))
    assert cm.costmap.origin == (1.0, -2.0) and cm.costmap.costs.shape == (80, 90)
    data2 = data.copy()
    data2[40:45, 10:50] = 0
    data2[60, 60:70] = 100
    cm.set_map(_grid(data2, (1.0, -2.0)))
    cm.update((3.0, 0.0, 0.0))
    fresh = LayeredCostmap(cfg)
    fresh.set_map(_grid(data2, (1.0, -2.0)))
    fresh.update((3.0, 0.0, 0.0))
    np.testing.assert_array_equal(cm.costmap.costs, fresh.costmap.costs)


def _local_cfg(**kw):
    base = dict(rolling_window=True, static_map=False, width=4.0, height=4.0, resolution=0.05,
                global_frame="odom", observation_sources="scan", marking=True, clearing=True,
                obstacle_range=2.5, raytrace_range=3.0, inflation_radius=0.3,
                cost_scaling_factor=10.0, track_unknown_space=False,
                footprint=((-0.1, -0.1), (-0.1, 0.1), (0.1, 0.1), (0.1, -0.1)))
    base.update(kw)
    return CostmapConfig(**base)


def test_obstacle_layer_marks_clears_and_rolls():
    cm = LayeredCostmap(_local_cfg())
    cm.add_scan((0.0, 0.0, 0.0), np.array([[1.0, 0.0], [0.0, 3.5]]))
    cm.update((0.0, 0.0, 0.0))
    cost = cm.costmap
    cell = cost.world_to_map(1.0, 0.0)
    assert cost.costs[cell[1], cell[0]] == LETHAL
    far = cost.world_to_map(0.0, 1.9)           # on the 3.5 m ray: beyond obstacle_range
    assert cost.costs[far[1], far[0]] == FREE
    # a later scan passing through the mark clears it
    cm.add_scan((0.0, 0.0, 0.0), np.array([[1.83, 0.01]]))
    cm.update((0.0, 0.0, 0.0))
    assert cost.costs[cell[1], cell[0]] < INSCRIBED
    # marks stay put in the world frame when the window rolls
    cm.update((0.6, 0.3, 0.0))
    moved = cm.costmap.world_to_map(1.83, 0.01)
    assert cm.costmap.costs[moved[1], moved[0]] == LETHAL
    assert cm.costmap.origin[0] == pytest.approx(0.6 - 2.0, abs=0.05)


def test_obstacle_layer_clears_robot_footprint_and_recovery():
    cm = LayeredCostmap(_local_cfg())
    cm.add_scan((0.0, 0.0, 0.0), np.array([[0.05, 0.0], [1.5, 1.5], [0.5, 0.0]]))
    cm.update((0.0, 0.0, 0.0))
    c = cm.costmap
    under = c.world_to_map(0.05, 0.0)
    assert c.costs[under[1], under[0]] != LETHAL
    near = c.world_to_map(0.5, 0.0)
    far = c.world_to_map(1.5, 1.5)
    assert c.costs[near[1], near[0]] == LETHAL and c.costs[far[1], far[0]] == LETHAL
    cm.clear_outside((0.0, 0.0, 0.0), 2.0)
    cm.update((0.0, 0.0, 0.0))
    assert c.costs[near[1], near[0]] == LETHAL
    assert c.costs[far[1], far[0]] == FREE


def test_footprint_clearing_disabled_keeps_an_obstacle_under_the_footprint():
    cm = LayeredCostmap(_local_cfg(footprint_clearing_enabled=False))
    cm.add_scan((0.0, 0.0, 0.0), np.array([[0.05, 0.0], [0.5, 0.0]]))
    cm.update((0.0, 0.0, 0.0))
    c = cm.costmap
    under = c.world_to_map(0.05, 0.0)
    near = c.world_to_map(0.5, 0.0)
    assert c.costs[under[1], under[0]] == LETHAL and c.costs[near[1], near[0]] == LETHAL


@pytest.mark.parametrize("dtype", [np.uint8, np.int8])
@pytest.mark.parametrize("seed", range(5))
def test_changed_box_bounds_every_changed_cell(seed, dtype):
    """changed_box equals the box of np.nonzero(new != old), or None when nothing changed."""
    rng = np.random.default_rng(seed)
    old = rng.integers(0, 3, size=(40, 57)).astype(dtype)
    new = old.copy()
    assert changed_box(new, old) is None
    for _ in range(int(rng.integers(1, 6))):
        new[rng.integers(40), rng.integers(57)] += 1
    ys, xs = np.nonzero(new != old)
    assert changed_box(new, old) == (xs.min(), ys.min(), xs.max() + 1, ys.max() + 1)


@pytest.mark.parametrize("seed", range(4))
def test_static_layer_updates_only_what_changed_and_bounds_it_as_before(seed):
    """A sequence of maps: the static costs equal a fresh interpretation of the latest map,
    and the dirty box is the box of changed costs (the whole-grid rule)."""
    rng = np.random.default_rng(seed)
    cfg = CostmapConfig(static_map=True, track_unknown_space=True, observation_sources="",
                        trinary_costmap=bool(seed % 2), lethal_cost_threshold=65)
    data = rng.choice(np.array([-1, 0, 30, 70, 100], np.int8), size=(50, 64))
    cm = LayeredCostmap(cfg)
    cm.set_map(_grid(data))
    for _ in range(6):
        before = cm._static.copy()
        cm._dirty = None
        new = data.copy()
        y, x = rng.integers(0, 45), rng.integers(0, 60)
        new[y:y + rng.integers(0, 6), x:x + rng.integers(0, 5)] = rng.choice([-1, 0, 20, 100])
        cm.set_map(_grid(new))
        expected = static_costs(new, cfg)
        np.testing.assert_array_equal(cm._static, expected)
        assert cm._dirty == changed_box(expected, before)
        data = new


@pytest.mark.parametrize("dtype, value", [(np.uint8, 255), (np.int8, -1)])
@pytest.mark.parametrize("seed", range(5))
def test_other_box_bounds_every_cell_of_another_value(seed, dtype, value):
    """kernels.other_box equals the box of np.nonzero(grid != value), (-1,)*4 when none."""
    from slam_predict.nav.kernels import other_box

    rng = np.random.default_rng(seed)
    grid = np.full((37, 51), value, dtype)
    assert other_box(grid, dtype(value)) == (-1, -1, -1, -1)
    for _ in range(int(rng.integers(1, 6))):
        grid[rng.integers(37), rng.integers(51)] = rng.integers(0, 100)
    ys, xs = np.nonzero(grid != value)
    assert other_box(grid, dtype(value)) == (xs.min(), ys.min(), xs.max() + 1, ys.max() + 1)
