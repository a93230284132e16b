"""Readers of a costs grid that look only where it was written, against the whole-grid passes
they replace: the write log's boxes, the known-cells box, the plan cache's compare."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from slam_predict.nav.changes import KnownBox, WriteLog, equal_within, other_box_within
from slam_predict.nav.config import CostmapConfig
from slam_predict.nav.costmap import NO_INFORMATION, Costmap
from slam_predict.nav.kernels import other_box
from slam_predict.nav.layered import LayeredCostmap
from slam_predict.nav.planner import LastPlan


def ref_box(grid: np.ndarray, value: int):
    """The box of the cells other than ``value``, with np.nonzero."""
    ys, xs = np.nonzero(grid != value)
    if len(xs) == 0:
        return (-1, -1, -1, -1)
    return (int(xs.min()), int(ys.min()), int(xs.max()) + 1, int(ys.max()) + 1)


def random_box(rng, nx: int, ny: int):
    """A box of the grid, often touching its borders, now and then a single cell."""
    x0, x1 = sorted(rng.integers(0, nx, 2))
    y0, y1 = sorted(rng.integers(0, ny, 2))
    if rng.random() < 0.2:
        x0, x1 = 0, nx
    if rng.random() < 0.2:
        y0, y1 = (ny - 1, ny) if rng.random() < 0.5 else (0, 1)
    return int(x0), int(y0), int(max(x1, x0 + 1)), int(max(y1, y0 + 1))


def write(rng, cm: Costmap, box) -> None:
    """Write into ``box`` of a logged costmap: unknown, other values, the same values again,
    or nothing new at all; then record the box, as the layered costmap does."""
    x0, y0, x1, y1 = box
    window = cm.costs[y0:y1, x0:x1]
    kind = rng.integers(4)
    if kind == 0:
        window[...] = NO_INFORMATION
    elif kind == 1:
        window[...] = np.where(rng.random(window.shape) < 0.3, rng.integers(0, 256),
                               NO_INFORMATION)
    elif kind == 2:
        window[...] = window.copy()
    else:
        window[rng.random(window.shape) < 0.05] = rng.integers(0, 255)
    cm.log.record(box)


def logged(costs: np.ndarray) -> Costmap:
    return Costmap(costs, (0.0, 0.0), 0.05, WriteLog(costs, keep=3))


@pytest.mark.parametrize("seed", range(20))
def test_other_box_within_the_whole_grid_is_the_box_of_np_nonzero(seed):
    rng = np.random.default_rng(seed)
    shape = tuple(int(v) for v in rng.integers(1, 30, 2))
    grid = np.full(shape, NO_INFORMATION, np.uint8)
    if seed % 4:
        grid[rng.random(shape) < rng.choice([0.002, 0.05, 0.5])] = rng.integers(0, 255)
    if seed % 5 == 1:
        grid[-1, -1] = 0                                   # a corner cell alone
    box = other_box_within(grid, np.uint8(NO_INFORMATION), 0, 0, shape[1], shape[0])
    assert box == ref_box(grid, NO_INFORMATION) == other_box(grid, np.uint8(NO_INFORMATION))


@pytest.mark.parametrize("seed", range(10))
def test_the_log_holds_every_changed_cell_in_the_box_it_gives(seed):
    """Between any two looks, every cell that changed is inside since(count); with nothing
    recorded since, since() is None; a reader older than the kept boxes gets the grid."""
    rng = np.random.default_rng(seed)
    cm = logged(np.full((17, 23), NO_INFORMATION, np.uint8))
    looks = [(0, cm.costs.copy())]
    for _ in range(40):
        write(rng, cm, random_box(rng, 23, 17))
        looks.append((cm.log.count, cm.costs.copy()))
        for count, seen in looks[-12:]:
            box = cm.log.since(count)
            ys, xs = np.nonzero(seen != cm.costs)
            if count == cm.log.count:
                assert box is None
                continue
            x0, y0, x1, y1 = box
            assert np.all((xs >= x0) & (xs < x1) & (ys >= y0) & (ys < y1))
    assert cm.log.since(0) == (0, 0, 23, 17)               # boxes no longer kept
    count = cm.log.count
    cm.log.record((-3, 16, 99, 40))                        # kept clipped to the grid
    assert cm.log.since(count) == (0, 16, 23, 17)


@pytest.mark.parametrize("seed", range(12))
def test_known_box_equals_the_whole_grid_pass_after_every_write(seed):
    """First call, writes at the borders, a grid turning all unknown and back, a new grid of
    the same or another shape (a resized layered costmap), a grid without a log."""
    rng = np.random.default_rng(seed)
    known = KnownBox(NO_INFORMATION)
    cm = logged(np.full((19, 26), NO_INFORMATION, np.uint8))
    for step in range(60):
        if step % 25 == 24:
            shape = (19, 26) if rng.random() < 0.5 else tuple(rng.integers(1, 30, 2))
            cm = logged(np.full(shape, NO_INFORMATION, np.uint8))
        for _ in range(int(rng.integers(0, 3))):
            ny, nx = cm.costs.shape
            write(rng, cm, random_box(rng, nx, ny))
        ref = other_box(cm.costs, np.uint8(NO_INFORMATION))
        assert known.of(cm) == ref
        if step % 7 == 3:                                  # a grid without a log: read whole
            assert known.of(SimpleNamespace(costs=cm.costs.copy())) == ref


def whole_compare(key, costs, last_key, last_costs) -> bool:
    """The plan cache's rule read whole: the same key and every cost the same."""
    return key == last_key and costs.shape == last_costs.shape and np.array_equal(
        costs, last_costs)


@pytest.mark.parametrize("seed", range(12))
def test_plan_cache_hits_exactly_when_the_whole_grid_is_unchanged(seed):
    """LastPlan's compare inside the written box against np.array_equal of the whole grid,
    through writes that change nothing, writes at the borders, key changes, a costmap
    replaced by one of the same shape (new log) or another, costmaps without a log, and
    readers that fell behind the kept boxes."""
    rng = np.random.default_rng(100 + seed)
    cache = LastPlan()
    last_key, last_costs = None, np.zeros((0, 0), np.uint8)
    cm = logged(np.full((15, 21), NO_INFORMATION, np.uint8))
    hits = misses = 0
    for step in range(150):
        if step % 40 == 39:
            shape = (15, 21) if rng.random() < 0.5 else tuple(rng.integers(2, 25, 2))
            cm = logged(np.full(shape, NO_INFORMATION, np.uint8))
        for _ in range(int(rng.choice([0, 0, 1, 1, 6]))):
            ny, nx = cm.costs.shape
            write(rng, cm, random_box(rng, nx, ny))
        key = int(rng.integers(2))
        asked = cm if step % 11 else SimpleNamespace(costs=cm.costs)
        hit = cache.matches(key, asked)
        assert hit == whole_compare(key, cm.costs, last_key, last_costs)
        if hit:
            hits += 1
            continue
        misses += 1
        cache.remember(key, asked, None, 0)
        last_key, last_costs = key, cm.costs.copy()
        np.testing.assert_array_equal(cache.costs, cm.costs)
    assert hits > 20 and misses > 20


def test_equal_within_is_the_window_compare():
    rng = np.random.default_rng(1)
    a = rng.integers(0, 256, (9, 12)).astype(np.uint8)
    b = a.copy()
    b[8, 11] ^= 1
    assert equal_within(a, b, 0, 0, 11, 9) and equal_within(a, b, 0, 0, 12, 8)
    assert not equal_within(a, b, 11, 8, 12, 9) and not equal_within(a, b, 0, 0, 12, 9)
    assert equal_within(a, b, 5, 5, 5, 9)                  # an empty window


def _layered_cfg(**kw):
    base = dict(static_map=True, track_unknown_space=True, inflation_radius=0.3,
                cost_scaling_factor=5.0, observation_sources="scan", marking=True,
                clearing=True, obstacle_range=2.0, raytrace_range=2.5,
                footprint=((-0.2, -0.2), (-0.2, 0.2), (0.2, 0.2), (0.2, -0.2)))
    base.update(kw)
    return CostmapConfig(**base)


@pytest.mark.parametrize("rolling", [False, True])
def test_layered_costmap_records_every_cell_it_changes(rolling):
    """A layered costmap (new maps, scans, footprint clearing, recoveries, a rolling window)
    logs boxes holding every cost it changes; a resize gives a new costmap with a new log."""
    rng = np.random.default_rng(3)
    cfg = _layered_cfg(rolling_window=rolling, width=3.0, height=3.0, resolution=0.05,
                       footprint_clearing_enabled=True)
    layered = LayeredCostmap(cfg)
    data = np.full((60, 70), -1, np.int8)
    for step in range(30):
        data[rng.random(data.shape) < 0.05] = rng.choice([-1, 0, 100])
        grid = SimpleNamespace(data=data.copy(), origin=(0.0, 0.0) if step < 20 else (0.5, 0.0),
                               resolution=0.05)
        layered.set_map(grid)
        pose = (1.0 + 0.1 * step, 1.5, 0.3 * step)
        points = pose[:2] + rng.uniform(-2.0, 2.0, (20, 2))
        layered.add_scan(pose, points)
        if step == 12:
            layered.clear_outside(pose, 1.0)
        cm = layered.costmap
        before, count = cm.costs.copy(), cm.log.count
        layered.update(pose)
        if layered.costmap is not cm:
            continue
        assert cm.log.costs is cm.costs
        ys, xs = np.nonzero(before != cm.costs)
        box = cm.log.since(count)
        if box is None:
            assert len(xs) == 0
            continue
        x0, y0, x1, y1 = box
        assert np.all((xs >= x0) & (xs < x1) & (ys >= y0) & (ys < y1))


def claimed_maps(rng, shape=(40, 50), steps=25):
    """SLAM-like maps: a known region that grows, shrinks and moves, with cells changing
    inside it; each with a ``known`` box holding it (sometimes loose, sometimes empty)."""
    maps = []
    for _ in range(steps):
        data = np.full(shape, -1, np.int8)
        x0, x1 = sorted(rng.integers(0, shape[1], 2))
        y0, y1 = sorted(rng.integers(0, shape[0], 2))
        if rng.random() < 0.1:
            x1 = x0                                            # nothing known
        window = data[y0:y1, x0:x1]
        window[...] = np.where(rng.random(window.shape) < 0.1, 100, 0)
        window[rng.random(window.shape) < 0.2] = -1
        loose = int(rng.integers(0, 3))
        maps.append((data, (max(0, x0 - loose), max(0, y0 - loose), x1 + loose, y1 + loose)))
        if rng.random() < 0.3:
            maps.append((data.copy(), maps[-1][1]))          # the same map again
    return maps


@pytest.mark.parametrize("seed", range(6))
def test_static_layer_with_known_boxes_equals_the_whole_map_compare(seed):
    """Global costmaps given the same maps with and without their ``known`` boxes (the
    whole-map compare) hold the same costs after every update."""
    rng = np.random.default_rng(seed)
    cfg = _layered_cfg(observation_sources="", resolution=0.05)
    told, whole = LayeredCostmap(cfg), LayeredCostmap(cfg)
    for data, known in claimed_maps(rng):
        told.set_map(SimpleNamespace(data=data, origin=(0.0, 0.0), resolution=0.05,
                                     known=known))
        whole.set_map(SimpleNamespace(data=data, origin=(0.0, 0.0), resolution=0.05))
        assert told._dirty == whole._dirty
        told.update((1.0, 1.0, 0.0))
        whole.update((1.0, 1.0, 0.0))
        np.testing.assert_array_equal(told.costmap.costs, whole.costmap.costs)


@pytest.mark.parametrize("seed", range(6))
def test_frontier_cache_with_known_boxes_searches_when_the_whole_compare_says(seed):
    """The explorer's ClusterCache searches again exactly when the map's cells changed, also
    when only some grids tell a ``known`` box."""
    from slam_predict.explore.frontiers import ClusterCache

    rng = np.random.default_rng(seed)
    cache, last = ClusterCache(), None
    for data, known in claimed_maps(rng, steps=40):
        grid = SimpleNamespace(data=data, origin=(0.0, 0.0), resolution=0.1,
                               known=known if rng.random() < 0.8 else None)
        before = cache._data
        cache.clusters(grid, 0.3, 0.0)
        searched = cache._data is not before
        assert searched == (last is None or not np.array_equal(data, last))
        last = data
