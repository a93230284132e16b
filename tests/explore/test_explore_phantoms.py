"""Phantom frontiers inside a grazed wall (``min_unknown_width``): the unknown sliver between
the two occupied faces of a wall is no frontier, a doorway into an unexplored room still is."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from slam_predict.explore.explorer import ExploreConfig, Explorer
from slam_predict.explore.frontiers import find_frontiers, frontier_mask, roomy_unknown

RES = 0.05


def grazed_wall_grid():
    """0.05 m cells, origin (0, 0): a corridor (y 0.5–1.0 m) along a 4-cell wall (y 1.0–1.2 m)
    whose faces are occupied and whose inside was partly marked free by grazing beams (free
    cells at x 0.5–3.0 m with unknown cells next to them, inside the wall); a mapped room above
    the wall (x < 4 m), and a doorway (x 4.4–5.4 m) into an unexplored room (x > 4.2 m)."""
    data = np.full((60, 120), -1, np.int8)
    data[9, :111] = 100                        # the corridor's other wall
    data[10:20, :111] = 0                      # corridor (rows 10-19)
    data[20:24, :111] = 100                    # wall band rows 20-23
    data[21, 10:61] = 0                        # grazed: free inside the wall...
    data[22, 10:61] = -1                       # ...and unknown next to them...
    data[22, 10:61:5] = 0                      # ...with a few more free cells
    data[24:44, :81] = 0                       # the mapped room above the wall
    data[44, :82] = 100
    data[24:45, 81] = 100
    data[20:24, 88:108] = 0                    # the doorway, room beyond unknown
    return SimpleNamespace(data=data, resolution=RES, origin=(0.0, 0.0))


def test_roomy_unknown_keeps_only_unknown_joined_to_a_square():
    unknown = np.zeros((12, 12), bool)
    unknown[1, 1:11] = True                    # a 1-cell sliver
    unknown[5:10, 5:10] = True                 # a 5 x 5 block
    unknown[4, 7] = True                       # a cell joined to the block
    kept = roomy_unknown(unknown, 5)
    assert not kept[1].any()
    assert kept[5:10, 5:10].all() and kept[4, 7]
    assert (roomy_unknown(unknown, 1) == unknown).all()
    assert not roomy_unknown(unknown, 6).any()
    edge = np.zeros((6, 6), bool)
    edge[:2, :] = True                         # unknown beyond the array counts
    assert roomy_unknown(edge, 3)[:2].all()


def wall_frontier(frontiers):
    """Frontiers lying in the wall band left of the doorway."""
    return [f for f in frontiers
            if np.all((f.cells[:, 1] > 1.0) & (f.cells[:, 1] < 1.2) & (f.cells[:, 0] < 3.1))]


def doorway_frontier(frontiers):
    return [f for f in frontiers if np.all((f.cells[:, 0] > 4.3) & (f.cells[:, 0] < 5.5))
            and f.cells[:, 1].max() > 1.1]


def test_grazed_wall_is_a_frontier_by_explore_lite_rule_only():
    grid = grazed_wall_grid()
    plain = find_frontiers(grid, (1.5, 0.7), 0.5)
    assert len(wall_frontier(plain)) == 1 and wall_frontier(plain)[0].size >= 40
    assert plain[0] is wall_frontier(plain)[0]          # the phantom is the nearest
    roomy = find_frontiers(grid, (1.5, 0.7), 0.5, min_unknown_width=0.25)
    assert wall_frontier(roomy) == []
    assert len(doorway_frontier(roomy)) == 1
    assert doorway_frontier(roomy)[0].size == doorway_frontier(plain)[0].size
    mask = frontier_mask(grid.data, 5)
    assert not mask[21].any() and mask[23, 88:108].all()


def test_explorer_skips_the_phantom_and_goes_to_the_doorway():
    grid = grazed_wall_grid()
    robot = np.array([1.5, 0.7, 0.0])
    sent = {}
    for width in (0.0, 0.25):
        cfg = ExploreConfig(goal_clearance=0.0, near_frontier_distance=0.1,
                            min_unknown_width=width)
        goals = []
        client = SimpleNamespace(send_goal=lambda target, t, goals=goals: goals.append(target),
                                 status=lambda: None, plan_length=lambda: None,
                                 cancel=lambda t: None)
        Explorer(cfg, client, np.random.default_rng(0)).step(0.0, grid, robot)
        sent[width] = goals[0]
    assert 1.0 < sent[0.0][1] < 1.2                      # into the wall
    assert 4.3 < sent[0.25][0] < 5.5 and sent[0.25][1] > 1.1      # the doorway


def test_config_rejects_negative_min_unknown_width():
    with pytest.raises(ValueError):
        ExploreConfig(min_unknown_width=-0.1)


def test_open_ends_at_the_edge_of_the_known_area_stay_frontiers():
    """Unknown space just beyond the known cells is roomy, wherever the known area ends."""
    data = np.full((40, 40), -1, np.int8)
    data[15:25, 10:30] = 0                     # a known free strip, unknown all around
    grid = SimpleNamespace(data=data, resolution=RES, origin=(0.0, 0.0))
    plain = find_frontiers(grid, (1.0, 1.0), 0.2)
    roomy = find_frontiers(grid, (1.0, 1.0), 0.2, min_unknown_width=0.25)
    assert sum(f.size for f in roomy) == sum(f.size for f in plain) == 56


def reference_roomy_unknown(unknown: np.ndarray, width: int) -> np.ndarray:
    """The definition, with scipy's binary morphology: erosion by a width x width square
    (outside = unknown), then propagation through unknown cells (4-connected)."""
    from scipy import ndimage
    core = ndimage.binary_erosion(unknown, np.ones((width, width), bool), border_value=1)
    return ndimage.binary_propagation(core, mask=unknown)


@pytest.mark.parametrize("width", [2, 3, 4, 5, 6, 9])
def test_roomy_unknown_equals_the_morphological_definition(width):
    rng = np.random.default_rng(width)
    for density in (0.3, 0.6, 0.85, 0.95):
        unknown = rng.random((57, 83)) < density
        unknown[20:35, 30:60] = True           # a large unknown block
        assert (roomy_unknown(unknown, width) == reference_roomy_unknown(unknown, width)).all()
    sliver = grazed_wall_grid().data == -1
    assert (roomy_unknown(sliver, width) == reference_roomy_unknown(sliver, width)).all()


def reference_frontier_mask(data: np.ndarray, width: int) -> np.ndarray:
    """The definition with whole-array numpy: free cells with a 4-neighbour in the
    morphological roomy unknown (neighbours beyond the array do not count)."""
    unknown = data == -1
    roomy = reference_roomy_unknown(unknown, width) if width > 1 else unknown
    near = np.zeros_like(roomy)
    near[1:, :] |= roomy[:-1, :]
    near[:-1, :] |= roomy[1:, :]
    near[:, 1:] |= roomy[:, :-1]
    near[:, :-1] |= roomy[:, 1:]
    return (data == 0) & near


@pytest.mark.parametrize("width", [0, 1, 2, 5, 6])
def test_frontier_mask_equals_the_definition_on_random_grids(width):
    """Random grids of free, unknown and occupied cells with unknown blocks, some touching the
    border, and a non-contiguous slice of one (as the known box is)."""
    rng = np.random.default_rng(100 + width)
    for _ in range(20):
        data = rng.choice(np.array([-1, 0, 100], np.int8), size=(41, 67), p=[0.4, 0.45, 0.15])
        r, c = rng.integers(0, 30, 2)
        data[r:r + 12, c:c + 20] = -1
        assert (frontier_mask(data, width) == reference_frontier_mask(data, width)).all()
        part = data[3:37, 5:60]
        assert (frontier_mask(part, width) == reference_frontier_mask(part, width)).all()


def reference_clusters(mask: np.ndarray) -> list[np.ndarray]:
    """scipy's 8-connected labelling: each label's (row, col) cells in raster order, by label."""
    from scipy import ndimage
    labels, count = ndimage.label(mask, structure=np.ones((3, 3), bool))
    rows, cols = np.nonzero(labels)
    return [np.stack([rows[labels[rows, cols] == k], cols[labels[rows, cols] == k]], axis=1)
            for k in range(1, count + 1)]


def test_clusters_are_scipy_labels_in_their_order():
    """Random masks, sparse to dense, and a frontier mask: the same components, numbered in
    scipy's order, with the same cells in the same order."""
    from slam_predict.explore.kernels import clusters_in_raster_order
    rng = np.random.default_rng(7)
    masks = [rng.random((45, 70)) < p for p in (0.02, 0.1, 0.3, 0.6, 0.9)]
    masks.append(frontier_mask(grazed_wall_grid().data, 0))
    masks.append(np.zeros((5, 5), bool))
    for mask in masks:
        rows, cols, starts = clusters_in_raster_order(mask)
        ours = [np.stack([rows[a:b], cols[a:b]], axis=1) for a, b in zip(starts[:-1],
                                                                          starts[1:], strict=True)]
        theirs = reference_clusters(mask)
        assert len(ours) == len(theirs)
        assert all((o == t).all() for o, t in zip(ours, theirs, strict=True))
