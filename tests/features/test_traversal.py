"""Voronoi traversal: kernels against the plain-Python reference, and known answers."""
from __future__ import annotations

import math

import networkx as nx
import numpy as np
import pytest

from slam_predict.features import kernels, traversal
from slam_predict.features.traversal import (
    TraversalConfig,
    polyline_turning,
    simplify_polyline,
    traverse,
)
from slam_predict.features.voronoi import VoronoiConfig, VoronoiGraph, voronoi_graph

from . import reference
from .plans import Plan, corridor_with_rooms, single_room


def random_map(rng: np.random.Generator, rows=40, cols=50, blocks=12) -> np.ndarray:
    occ = np.zeros((rows, cols), bool)
    occ[0], occ[-1], occ[:, 0], occ[:, -1] = True, True, True, True
    for _ in range(blocks):
        r, c = rng.integers(1, rows - 3), rng.integers(1, cols - 3)
        occ[r:r + rng.integers(1, 6), c:c + rng.integers(1, 6)] = True
    return occ


@pytest.mark.parametrize("seed", range(6))
def test_line_of_sight_matches_reference(seed):
    rng = np.random.default_rng(seed)
    occ = random_map(rng)
    clearance = traversal.clearance_px(occ)
    free = np.argwhere(~occ)
    for _ in range(300):
        a, b = free[rng.integers(len(free))], free[rng.integers(len(free))]
        want = reference.visible(occ.tolist(), a, b)
        assert kernels.line_is_free(occ, a[0], a[1], b[0], b[1]) == want
        assert kernels.line_is_free_fast(occ, clearance, a[0], a[1], b[0], b[1]) == want


def test_digital_line_is_symmetric_in_extent():
    line = reference.digital_line(0, 0, 3, 7)
    assert line[-1] == (3, 7) and len(line) == 7
    assert all(abs(r1 - r0) <= 1 and c1 - c0 == 1
               for (r0, c0), (r1, c1) in zip(line, line[1:], strict=False))


def _random_graph(rng, occ, n=40):
    """Nodes on random free pixels, edges of a random spanning tree plus a few chords."""
    free = np.argwhere(~occ)
    rc = free[rng.choice(len(free), n, replace=False)]
    edges = [(i, int(rng.integers(i))) for i in range(1, n)]
    edges += [tuple(rng.choice(n, 2, replace=False)) for _ in range(n // 4)]
    edges = np.array(sorted({(min(a, b), max(a, b)) for a, b in edges}), np.int64)
    weights = np.hypot(*(rc[edges[:, 0]] - rc[edges[:, 1]]).T) * 0.05
    return VoronoiGraph(rc=rc.astype(np.int64), edges=edges, weights=weights,
                        skeleton=np.zeros_like(occ), interior=~occ, resolution=0.05)


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("mode", ["documented", "thesis_compatible"])
def test_traverse_matches_slow_reference(seed, mode):
    rng = np.random.default_rng(100 + seed)
    occ = random_map(rng)
    graph = _random_graph(rng, occ)
    config = TraversalConfig(laser_range_m=float(rng.uniform(0.5, 2.0)),
                             laser_fov=math.radians(260.0), min_rotation_distance_m=0.2, mode=mode)
    start_rc = np.argwhere(~occ)[rng.integers((~occ).sum())]
    yaw = float(rng.uniform(-math.pi, math.pi))
    fast = traverse(graph, occ, start_rc, yaw, config)
    compat = mode == "thesis_compatible"
    visits, dist_px, rotation = reference.traverse(
        occ, graph.rc, graph.edges, graph.weights, fast.start_node,
        math.pi / 2 if compat else yaw, 0.0 if compat else yaw,
        config.laser_range_m / 0.05, config.laser_fov / 2,
        config.min_rotation_distance_m / 0.05, hops=compat, reset_heading=compat)
    assert fast.start_node == int(np.argmin(((graph.rc - start_rc) ** 2).sum(axis=1)))
    np.testing.assert_array_equal(fast.path_rc, graph.rc[visits])
    assert fast.distance == pytest.approx(dist_px * 0.05, rel=1e-9)
    assert fast.rotation == pytest.approx(rotation, rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("seed", range(3))
def test_shortest_paths_match_networkx(seed):
    rng = np.random.default_rng(seed)
    occ = random_map(rng)
    graph = _random_graph(rng, occ, n=60)
    g = graph.to_networkx()
    indptr, indices, weights = graph.csr()
    for _ in range(20):
        a, b = (int(v) for v in rng.choice(graph.order, 2, replace=False))
        path = kernels.dijkstra_path(indptr, indices, weights, a, b)
        length = sum(g[u][v]["weight"] for u, v in zip(path[:-1], path[1:], strict=False))
        assert length == pytest.approx(nx.dijkstra_path_length(g, a, b))
        hops = kernels.bfs_path(indptr, indices, a, b)
        assert len(hops) - 1 == nx.shortest_path_length(g, a, b)


def test_every_node_is_seen_and_path_follows_edges():
    world = corridor_with_rooms(3).world()
    graph = voronoi_graph(world.occupied, world.resolution)
    result = traverse(graph, world.occupied, world.world_to_cell(world.start_pose[:2]),
                      0.0, TraversalConfig(laser_range_m=3.0))
    index = {tuple(p): i for i, p in enumerate(graph.rc)}
    edges = {tuple(e) for e in graph.edges}
    steps = [(index[tuple(a)], index[tuple(b)])
             for a, b in zip(result.path_rc, result.path_rc[1:], strict=False)]
    assert all((min(s), max(s)) in edges for s in steps)
    length = sum(np.hypot(*(a - b))
                 for a, b in zip(result.path_rc, result.path_rc[1:], strict=False))
    assert result.distance == pytest.approx(length * world.resolution)


def test_long_range_laser_sees_a_corridor_without_moving():
    plan = Plan(12.0, 3.0).room("corridor", (0.5, 0.5, 11.5, 2.5))
    world = plan.world(start_xy=(6.0, 1.5))
    graph = voronoi_graph(world.occupied, world.resolution)
    omni = TraversalConfig(laser_fov=2 * math.pi)
    result = traverse(graph, world.occupied, world.world_to_cell(world.start_pose[:2]), 0.0,
                      omni)
    assert result.distance == 0.0 and result.rotation == 0.0


def test_short_range_laser_walks_the_corridor():
    plan = Plan(22.0, 3.0).room("corridor", (0.5, 0.5, 21.5, 2.5))
    world = plan.world(start_xy=(1.5, 1.5))
    graph = voronoi_graph(world.occupied, world.resolution)
    cfg = TraversalConfig(laser_range_m=4.0, laser_fov=2 * math.pi)
    result = traverse(graph, world.occupied, world.world_to_cell(world.start_pose[:2]), 0.0,
                      cfg)
    # the far end (x ≈ 21 m) must come within 4 m: at least ~16 m of walking, straight ahead
    assert 14.0 < result.distance < 21.0
    assert result.rotation < 0.3


def test_narrow_field_of_view_forces_a_turn():
    world = single_room(10.0, 3.0).world(start_xy=(5.7, 2.2), yaw=0.0)
    graph = voronoi_graph(world.occupied, world.resolution)
    rc = world.world_to_cell(world.start_pose[:2])
    wide = traverse(graph, world.occupied, rc, 0.0, TraversalConfig(laser_fov=2 * math.pi))
    narrow = traverse(graph, world.occupied, rc, 0.0, TraversalConfig(laser_fov=math.pi / 2))
    assert wide.distance == 0.0
    assert narrow.distance > 2.0 and narrow.rotation > 2.0  # walks west, turning round


def test_thesis_compatible_mode_runs_on_thesis_graph():
    world = corridor_with_rooms(2).world()
    graph = voronoi_graph(world.occupied, world.resolution, VoronoiConfig(thesis_compatible=True))
    result = traverse(graph, world.occupied, world.world_to_cell(world.start_pose[:2]), 0.0,
                      TraversalConfig(mode="thesis_compatible"))
    assert result.distance > 0 and result.scans > 1


def test_config_validation():
    with pytest.raises(ValueError, match="mode"):
        TraversalConfig(mode="fast")
    with pytest.raises(ValueError):
        TraversalConfig(laser_fov_deg=400.0)


def test_simplify_and_turning():
    square = np.array([[0, 0], [1, 0.01], [2, 0], [2, 1], [2, 2], [0, 2]], float)
    simple = simplify_polyline(square, 0.1)
    np.testing.assert_allclose(simple, [[0, 0], [2, 0], [2, 2], [0, 2]])
    assert polyline_turning(simple) == pytest.approx(math.pi)
    back_and_forth = np.array([[0, 0], [3, 0], [0, 0]], float)
    assert polyline_turning(simplify_polyline(back_and_forth, 0.5)) == pytest.approx(math.pi)
    assert polyline_turning(np.zeros((2, 2))) == 0.0
