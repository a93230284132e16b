"""Voronoi graph: medial axis, thinning, sparsification, known topologies."""
from __future__ import annotations

import networkx as nx
import numpy as np
import pytest
from scipy import ndimage

from slam_predict.features import raster_kernels, rooms, voronoi
from slam_predict.features.skeleton_graph import pixel_edges, simplify_chains, sparsify
from slam_predict.features.voronoi import (
    VoronoiConfig,
    building_interior,
    nearest_site,
    skeleton_of,
    voronoi_graph,
)

from . import reference
from .plans import Plan, corridor_with_rooms, ring_corridor, single_room


def cycles(graph) -> int:
    """Cyclomatic number m − n + components."""
    g = graph.to_networkx()
    return g.number_of_edges() - g.number_of_nodes() + nx.number_connected_components(g)


@pytest.mark.parametrize("seed", range(4))
def test_guo_hall_matches_reference(seed):
    rng = np.random.default_rng(seed)
    img = np.zeros((40, 50), bool)
    for _ in range(8):
        r, c = rng.integers(0, 35), rng.integers(0, 45)
        img[r:r + rng.integers(2, 12), c:c + rng.integers(2, 20)] = True
    thin = raster_kernels.thin_guo_hall(img)
    np.testing.assert_array_equal(thin, reference.guo_hall(img))
    assert not (thin & ~img).any()
    eight = np.ones((3, 3))
    assert ndimage.label(thin, eight)[1] == ndimage.label(img, eight)[1]  # topology kept


def test_thin_keeps_diagonal_branches():
    img = np.zeros((40, 60), np.uint8)
    import cv2
    cv2.line(img, (5, 5), (30, 30), 1, 5)
    cv2.line(img, (30, 30), (55, 5), 1, 5)
    thin = raster_kernels.thin_guo_hall(img.astype(bool))
    rows, cols = np.nonzero(thin)
    assert cols.min() <= 8 and cols.max() >= 52 and rows.min() <= 8  # both arms reach their ends


def test_nearest_site_is_nearest():
    rng = np.random.default_rng(3)
    sites = rng.random((30, 40)) < 0.02
    site_r, site_c = nearest_site(sites)
    dist = ndimage.distance_transform_edt(~sites)
    got = np.hypot(site_r - np.arange(30)[:, None], site_c - np.arange(40)[None, :])
    assert np.all(sites[site_r, site_c])
    assert np.abs(got - dist).max() <= 1.05  # OpenCV's feature transform: exact up to ~1 px


def test_interior_is_the_longest_contour():
    plan = single_room(8.0, 5.0)
    plan.occ[2:6, 2:6] = False  # a free speck outside the building outline
    interior = building_interior(~plan.occ)
    assert interior.sum() == pytest.approx(8.0 * 5.0 / 0.05 ** 2, rel=1e-6)


def test_straight_corridor_is_a_path_with_corner_forks():
    world = Plan(20.4, 3.4).room("c", (0.2, 0.2, 20.2, 3.2)).world()
    graph = voronoi_graph(world.occupied, world.resolution)
    deg = graph.degrees()
    assert cycles(graph) == 0
    assert (deg == 1).sum() == 4 and (deg == 3).sum() == 2  # a forked segment: >—<
    assert graph.weights.sum() == pytest.approx(17.0 + 4 * 1.414 * 1.5, rel=0.1)
    assert graph.order < 12  # the straight run is one edge


def test_ring_corridor_gives_one_cycle():
    world = ring_corridor().world()
    graph = voronoi_graph(world.occupied, world.resolution)
    assert cycles(graph) == 1
    assert graph.weights.sum() > 4 * 13.0  # the loop is about 4 × 14 m long


def test_corridor_with_rooms_is_a_tree_with_a_branch_per_room():
    k = 4
    world = corridor_with_rooms(k).world()
    graph = voronoi_graph(world.occupied, world.resolution)
    assert cycles(graph) == 0
    # every room adds a junction on the corridor line and a fork inside the room
    assert (graph.degrees() >= 3).sum() >= 2 * k


def test_largest_component_only():
    plan = corridor_with_rooms(2)
    plan.occ[5:40, 5:40] = True
    plan.occ[10:30, 10:30] = False  # an unreachable closet inside the outline
    world = plan.world()
    graph = voronoi_graph(world.occupied, world.resolution)
    assert not ((graph.rc[:, 0] < 40) & (graph.rc[:, 1] < 40)).any()


def test_pass_through_removal_on_a_straight_line():
    skeleton = np.zeros((5, 30), bool)
    skeleton[2, 2:28] = True
    index = np.full(skeleton.shape, -1, np.int64)
    rr, cc = np.nonzero(skeleton)
    index[rr, cc] = np.arange(rr.size)
    rc = np.stack([rr, cc], axis=1)
    edges, steps = pixel_edges(skeleton, index, simple=True)
    keep, new_edges, weights = sparsify(rc, edges, steps, skeleton, align_px=5.0)
    # nodes within 5 px of either end cannot see the line continue beyond their neighbour
    assert 2 < keep.size < 14
    assert weights.sum() == pytest.approx(25.0)
    g = nx.Graph([tuple(e) for e in new_edges])
    assert nx.is_connected(g) and g.number_of_edges() == g.number_of_nodes() - 1


def test_simplify_chains_keeps_corners_and_lengths():
    rc = np.array([[0, i] for i in range(10)] + [[i, 9] for i in range(1, 10)])
    edges = np.array([[i, i + 1] for i in range(len(rc) - 1)])
    keep, new_edges, weights = simplify_chains(rc, edges, np.ones(len(edges)), 0.5)
    assert sorted(map(tuple, rc[keep])) == [(0, 0), (0, 9), (9, 9)]
    assert weights.sum() == pytest.approx(18.0)
    ring = np.array([[0, 0], [0, 5], [5, 5], [5, 0]])
    keep, new_edges, _ = simplify_chains(ring, np.array([[0, 1], [1, 2], [2, 3], [3, 0]]),
                                         np.ones(4), 0.5)
    assert len(new_edges) >= 3  # a pure cycle stays a cycle


def test_thesis_compatible_graph_uses_unit_steps():
    world = corridor_with_rooms(2).world()
    ours = voronoi_graph(world.occupied, world.resolution)
    seed = voronoi_graph(world.occupied, world.resolution, VoronoiConfig(thesis_compatible=True))
    assert seed.order > ours.order  # no metric simplification
    steps = seed.weights / world.resolution
    np.testing.assert_allclose(steps, np.round(steps))  # every pixel step counts as 1


def test_graph_lengths_do_not_depend_on_resolution():
    totals = []
    for res in (0.05, 0.1):
        world = corridor_with_rooms(3, res=res).world()
        graph = voronoi_graph(world.occupied, world.resolution)
        totals.append((graph.weights.sum(), (graph.degrees() >= 3).sum()))
    assert totals[1][0] == pytest.approx(totals[0][0], rel=0.05)
    assert abs(int(totals[1][1]) - int(totals[0][1])) <= 1


def test_skeleton_shared_with_rooms_is_reused(monkeypatch):
    world = corridor_with_rooms(3).world()
    fresh = voronoi_graph(world.occupied, world.resolution)
    fresh_rooms = rooms.segment_grid(world.occupied, world.resolution, rooms.RoomsConfig())
    base = skeleton_of(world.occupied, world.resolution)

    def recomputed(*args, **kwargs):
        raise AssertionError("skeleton_of called although a skeleton was given")

    monkeypatch.setattr(voronoi, "skeleton_of", recomputed)
    graph = voronoi_graph(world.occupied, world.resolution, base=base)
    shared_rooms = rooms.segment_grid(world.occupied, world.resolution, rooms.RoomsConfig(), base)
    assert graph.skeleton is base.skeleton and graph.interior is base.interior
    assert graph.order > 0
    for name in ("rc", "edges", "weights"):
        np.testing.assert_array_equal(getattr(graph, name), getattr(fresh, name))
    assert shared_rooms.count == fresh_rooms.count > 1
    np.testing.assert_array_equal(shared_rooms.labels, fresh_rooms.labels)
