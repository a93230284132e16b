"""Graph metrics of the topological and Voronoi graphs (seed thesis §5.2.2), networkx-defined.

All distances are hop counts (networkx's unweighted defaults, as the seed used them):

* order n, size m, density 2m / (n(n − 1));
* diameter / radius: largest / smallest eccentricity; average shortest path length;
* bifurcation points (degree > 2) and terminal points (degree 1);
* mean and population std (numpy ``std``) of the node centralities: betweenness (normalised,
  ``networkx.betweenness_centrality``), closeness (``closeness_centrality``), eigenvector
  (``eigenvector_centrality_numpy``: unit-norm principal eigenvector of the adjacency) and
  Katz (``katz_centrality_numpy`` with α = 0.1, β = 1, normalised to unit norm).

:func:`metrics` computes them with one numba all-pairs BFS sweep (Brandes' accumulation) and
scipy sparse linear algebra, fast enough for Voronoi graphs of thousands of nodes;
:func:`metrics_networkx` is the networkx reference they are tested against. Both expect a
connected graph (callers pass the largest component); a graph without nodes gives zeros.
"""
from __future__ import annotations

import logging

import networkx as nx
import numpy as np
from scipy import sparse
from scipy.sparse import linalg as splinalg

from slam_predict.features import graph_kernels
from slam_predict.features.skeleton_graph import to_csr

LOG = logging.getLogger(__name__)
KATZ_ALPHA = 0.1
KATZ_BETA = 1.0
DENSE_LIMIT = 50  # up to this many nodes the eigenvector comes from dense LAPACK

# (name, unit, description) of every metric, in output order.
METRICS: tuple[tuple[str, str, str], ...] = (
    ("order", "count", "number of nodes"),
    ("size", "count", "number of edges"),
    ("density", "ratio", "2m / (n(n − 1))"),
    ("diameter", "hops", "largest eccentricity"),
    ("radius", "hops", "smallest eccentricity"),
    ("bifurcation_points", "count", "nodes of degree > 2"),
    ("terminal_points", "count", "nodes of degree 1"),
    ("avg_shortest_path_length", "hops", "mean hop distance over ordered node pairs"),
    ("betweenness_mean", "ratio", "mean normalised betweenness centrality"),
    ("betweenness_std", "ratio", "std of normalised betweenness centrality"),
    ("closeness_mean", "ratio", "mean closeness centrality"),
    ("closeness_std", "ratio", "std of closeness centrality"),
    ("eigenvector_mean", "ratio", "mean eigenvector centrality (unit-norm eigenvector)"),
    ("eigenvector_std", "ratio", "std of eigenvector centrality"),
    ("katz_mean", "ratio", "mean Katz centrality (α = 0.1, β = 1, unit norm)"),
    ("katz_std", "ratio", "std of Katz centrality"),
)


def _empty() -> dict[str, float]:
    return {name: 0.0 for name, _, _ in METRICS}


def _summary(prefix: str, values: np.ndarray) -> dict[str, float]:
    return {f"{prefix}_mean": float(np.mean(values)), f"{prefix}_std": float(np.std(values))}


def eigenvector_centrality(adj: sparse.csr_matrix) -> np.ndarray:
    """Unit-norm, positive principal eigenvector of a symmetric adjacency matrix."""
    n = adj.shape[0]
    if n == 1:
        return np.ones(1)
    if n <= DENSE_LIMIT:
        _, vectors = np.linalg.eigh(adj.toarray())
        vec = vectors[:, -1]
    else:
        # a fixed start vector: without one ARPACK starts from a random vector (numpy's global
        # generator), and the last digits of the result change from run to run
        _, vectors = splinalg.eigsh(adj.astype(float), k=1, which="LA", tol=1e-10,
                                    v0=np.ones(n))
        vec = vectors[:, 0]
    return vec / (np.sign(vec.sum()) * np.linalg.norm(vec))


def katz_centrality(adj: sparse.csr_matrix, alpha: float = KATZ_ALPHA,
                    beta: float = KATZ_BETA) -> np.ndarray:
    """Solution of (I − α·A) x = β·1, normalised to unit norm (networkx's numpy variant).

    When α ≥ 1/λ_max the series diverges; the linear solution is still returned, as networkx
    does, with a warning.
    """
    n = adj.shape[0]
    system = sparse.identity(n, format="csc") - alpha * adj.T.tocsc()
    x = splinalg.spsolve(system, np.full(n, beta)) if n > 1 else np.array([beta])
    if n > 1 and np.any(x <= 0):
        LOG.warning("Katz α = %g exceeds 1/λ_max of a %d-node graph: centralities not positive",
                    alpha, n)
    return x / (np.sign(x.sum()) * np.linalg.norm(x))


def metrics(n: int, edges: np.ndarray) -> dict[str, float]:
    """All metrics of the undirected graph with ``n`` nodes and ``edges`` (E, 2), E unique pairs."""
    if n == 0:
        return _empty()
    edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    m = len(edges)
    degree = np.bincount(edges.ravel(), minlength=n)
    indptr, indices, _ = to_csr(n, edges, np.ones(m))
    ecc, dist_sum, between = graph_kernels.all_pairs_hops(indptr, indices)
    pairs = n * (n - 1)
    out = {
        "order": float(n), "size": float(m),
        "density": 2.0 * m / pairs if n > 1 else 0.0,
        "diameter": float(ecc.max()), "radius": float(ecc.min()),
        "bifurcation_points": float(np.sum(degree > 2)),
        "terminal_points": float(np.sum(degree == 1)),
        "avg_shortest_path_length": float(dist_sum.sum() / pairs) if n > 1 else 0.0,
    }
    between = between / ((n - 1) * (n - 2)) if n > 2 else np.zeros(n)
    closeness = np.divide(n - 1, dist_sum, out=np.zeros(n), where=dist_sum > 0)
    adj = sparse.csr_matrix((np.ones(len(indices)), indices, indptr), shape=(n, n))
    out.update(_summary("betweenness", between))
    out.update(_summary("closeness", closeness))
    out.update(_summary("eigenvector", eigenvector_centrality(adj)))
    out.update(_summary("katz", katz_centrality(adj)))
    return out


def metrics_networkx(graph: nx.Graph) -> dict[str, float]:
    """The same metrics straight from networkx (slow reference for tests)."""
    n = graph.number_of_nodes()
    if n == 0:
        return _empty()
    degree = np.array([d for _, d in graph.degree()])
    out = {
        "order": float(n), "size": float(graph.number_of_edges()),
        "density": float(nx.density(graph)),
        "diameter": float(nx.diameter(graph)), "radius": float(nx.radius(graph)),
        "bifurcation_points": float(np.sum(degree > 2)),
        "terminal_points": float(np.sum(degree == 1)),
        "avg_shortest_path_length": float(nx.average_shortest_path_length(graph)),
    }
    values = {
        "betweenness": nx.betweenness_centrality(graph),
        "closeness": nx.closeness_centrality(graph),
        "eigenvector": (nx.eigenvector_centrality_numpy(graph) if n > 2 else
                        nx.eigenvector_centrality(graph, max_iter=10_000, tol=1e-14)),
        "katz": (nx.katz_centrality_numpy(graph, alpha=KATZ_ALPHA, beta=KATZ_BETA) if n > 1
                 else {0: 1.0}),
    }
    for prefix, table in values.items():
        out.update(_summary(prefix, np.array(list(table.values()), dtype=float)))
    return out
