"""Graph metrics: the fast implementation equals networkx's."""
from __future__ import annotations

import networkx as nx
import numpy as np
import pytest

from slam_predict.features.graph_metrics import METRICS, metrics, metrics_networkx
from slam_predict.features.voronoi import voronoi_graph

from .plans import corridor_with_rooms, ring_corridor


def _check(graph: nx.Graph) -> None:
    graph = nx.convert_node_labels_to_integers(graph)
    edges = np.array(graph.edges(), np.int64).reshape(-1, 2)
    fast = metrics(graph.number_of_nodes(), edges)
    slow = metrics_networkx(graph)
    assert list(fast) == [name for name, _, _ in METRICS]
    for name in fast:
        assert fast[name] == pytest.approx(slow[name], rel=1e-7, abs=1e-10), name


@pytest.mark.parametrize("seed", range(5))
def test_random_graphs_match_networkx(seed):
    _check(nx.random_labeled_tree(30 + 10 * seed, seed=seed))
    _check(nx.connected_watts_strogatz_graph(40 + 10 * seed, 4, 0.2, seed=seed))


@pytest.mark.parametrize("graph", [nx.path_graph(1), nx.path_graph(2), nx.path_graph(3),
                                   nx.cycle_graph(6), nx.star_graph(5), nx.complete_graph(5),
                                   nx.grid_2d_graph(4, 5)], ids=str)
def test_small_graphs_match_networkx(graph):
    _check(graph)


@pytest.mark.parametrize("plan", [corridor_with_rooms(3), ring_corridor()], ids=["comb", "ring"])
def test_voronoi_graphs_match_networkx(plan):
    world = plan.world()
    graph = voronoi_graph(world.occupied, world.resolution)
    _check(graph.to_networkx())


def test_large_graph_uses_sparse_eigensolver():
    _check(nx.random_labeled_tree(700, seed=1))  # above the dense limit


def test_known_values():
    star = metrics(6, np.array([[0, k] for k in range(1, 6)]))
    assert star["density"] == pytest.approx(2 * 5 / 30)
    assert (star["diameter"], star["radius"]) == (2.0, 1.0)
    assert (star["bifurcation_points"], star["terminal_points"]) == (1.0, 5.0)
    empty = metrics(0, np.zeros((0, 2), np.int64))
    assert all(v == 0.0 for v in empty.values())


def test_sparse_eigenvector_centrality_is_the_same_every_time():
    """ARPACK's start vector is fixed: a graph above the dense limit gives bit-identical
    centralities whatever numpy's global generator holds (it gave other last digits before)."""
    from scipy import sparse

    from slam_predict.features.graph_metrics import DENSE_LIMIT, eigenvector_centrality

    graph = nx.random_regular_graph(3, DENSE_LIMIT + 40, seed=5)
    adj = sparse.csr_matrix(nx.to_scipy_sparse_array(graph))
    results = []
    for state in (1, 2, 3):
        np.random.seed(state)
        results.append(eigenvector_centrality(adj))
    assert all(np.array_equal(results[0], r) for r in results[1:])
    reference = nx.eigenvector_centrality_numpy(graph)
    want = np.array([reference[v] for v in graph])
    assert np.allclose(results[0], want / np.linalg.norm(want), atol=1e-8)
