"""Graphs of one-pixel skeletons: pixel edges, the seed's sparsification, chain simplification.

* :func:`pixel_edges` — 8-neighbour edges between skeleton pixels (optionally without the
  diagonal of a staircase corner, whose two pixels already meet through a 4-neighbour).
* :func:`sparsify` — the seed's pass-through removal (:func:`graph_kernels.remove_pass_through`).
* :func:`simplify_chains` — Douglas–Peucker on every chain of degree-2 nodes: a node is kept
  only if the chain strays more than a tolerance from the straight line between kept nodes, so
  "straight run" is judged in metres rather than pixels.
* :func:`largest_component`, :func:`to_csr` — helpers.

Edges are (E, 2) int arrays of node indices, each undirected edge once, with a weight each.
"""
from __future__ import annotations

import math

import numpy as np
from scipy import sparse
from scipy.sparse import csgraph

from slam_predict.features import graph_kernels
from slam_predict.features.polyline import douglas_peucker

SQRT2 = math.sqrt(2.0)
# 8-neighbour offsets looking "forward" (each undirected pair once).
_FORWARD = ((0, 1), (1, -1), (1, 0), (1, 1))


def to_csr(n: int, edges: np.ndarray, weights: np.ndarray):
    """Symmetric CSR arrays (indptr, indices, weights) of an undirected edge list."""
    if edges.size == 0:
        return np.zeros(n + 1, np.int64), np.zeros(0, np.int64), np.zeros(0)
    rows = np.concatenate([edges[:, 0], edges[:, 1]])
    cols = np.concatenate([edges[:, 1], edges[:, 0]])
    vals = np.concatenate([weights, weights]).astype(float)
    order = np.lexsort((cols, rows))
    rows, cols, vals = rows[order], cols[order], vals[order]
    indptr = np.zeros(n + 1, np.int64)
    np.add.at(indptr, rows + 1, 1)
    return np.cumsum(indptr), cols.astype(np.int64), vals


def pixel_edges(skeleton: np.ndarray, index: np.ndarray, simple: bool):
    """8-neighbour edges (i, j) between skeleton pixels and their lengths in px.

    ``simple`` drops a diagonal edge when the two pixels share a 4-neighbour on the skeleton.
    """
    rows, cols = skeleton.shape
    pad = np.zeros((rows + 2, cols + 2), bool)
    pad[1:-1, 1:-1] = skeleton
    rr, cc = np.nonzero(skeleton)
    out_a, out_b, out_w = [], [], []
    for dr, dc in _FORWARD:
        ok = pad[rr + 1 + dr, cc + 1 + dc]
        diagonal = dr != 0 and dc != 0
        if diagonal and simple:
            ok &= ~(pad[rr + 1 + dr, cc + 1] | pad[rr + 1, cc + 1 + dc])
        a = index[rr[ok], cc[ok]]
        b = index[rr[ok] + dr, cc[ok] + dc]
        out_a.append(a)
        out_b.append(b)
        out_w.append(np.full(a.shape, SQRT2 if diagonal else 1.0))
    return (np.stack([np.concatenate(out_a), np.concatenate(out_b)], axis=1),
            np.concatenate(out_w))


def sparsify(rc: np.ndarray, edges: np.ndarray, weights: np.ndarray, skeleton: np.ndarray,
             align_px: float):
    """Remove pass-through nodes on straight runs; returns (kept ids, new edges, weights)."""
    n = rc.shape[0]
    slots = 8
    nbr = np.full((n, slots), -1, np.int64)
    wgt = np.zeros((n, slots))
    src = np.concatenate([edges[:, 0], edges[:, 1]])
    dst = np.concatenate([edges[:, 1], edges[:, 0]])
    both = np.concatenate([weights, weights])
    order = np.argsort(src, kind="stable")
    src, dst, both = src[order], dst[order], both[order]
    first = np.searchsorted(src, src, side="left")
    slot = np.arange(src.size) - first
    nbr[src, slot] = dst
    wgt[src, slot] = both
    alive = graph_kernels.remove_pass_through(nbr, wgt, rc[:, 0].astype(np.int64),
                                        rc[:, 1].astype(np.int64), skeleton, float(align_px),
                                        np.arange(n, dtype=np.int64))
    keep = np.nonzero(alive)[0]
    new_id = np.full(n, -1, np.int64)
    new_id[keep] = np.arange(keep.size)
    src = np.repeat(np.arange(n), slots)
    dst = nbr.ravel()
    w = wgt.ravel()
    ok = (dst > src) & alive[src]
    return keep, np.stack([new_id[src[ok]], new_id[dst[ok]]], axis=1), w[ok]


def largest_component(n: int, edges: np.ndarray):
    """Boolean mask of the nodes of the largest connected component (ties: lowest label)."""
    if n == 0:
        return np.zeros(0, bool)
    adj = sparse.coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
    _, labels = csgraph.connected_components(adj, directed=False)
    counts = np.bincount(labels)
    return labels == int(np.argmax(counts))


def simplify_chains(rc: np.ndarray, edges: np.ndarray, weights: np.ndarray,
                    tolerance_px: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Douglas–Peucker simplification of every chain of degree-2 nodes.

    Returns (kept node ids, edges in new ids, weights); an edge replacing part of a chain
    weighs the sum of the chain's edge weights. Nodes of degree ≠ 2 are always kept; a cycle
    made only of degree-2 nodes keeps its lowest-numbered node as anchor.
    """
    n = rc.shape[0]
    adjacency: list[dict[int, float]] = [dict() for _ in range(n)]
    for (a, b), w in zip(edges.tolist(), weights.tolist(), strict=False):
        adjacency[a][b] = adjacency[b][a] = min(w, adjacency[a].get(b, math.inf))
    degree = np.array([len(nb) for nb in adjacency])
    keep = degree != 2
    new_edges: dict[tuple[int, int], float] = {}
    walked_steps: set = set()
    walked_nodes: set = set()
    anchors = list(np.nonzero(keep)[0]) + list(np.nonzero(~keep)[0])
    for start in anchors:
        if not keep[start] and start in walked_nodes:
            continue
        keep[start] = True
        for first in list(adjacency[start]):
            if (start, first) in walked_steps:
                continue
            chain, steps = _walk(adjacency, degree, start, first)
            walked_steps.update(zip(chain[:-1], chain[1:], strict=False))
            walked_steps.update(zip(chain[1:], chain[:-1], strict=False))
            walked_nodes.update(chain)
            kept = douglas_peucker(rc[chain].astype(float), tolerance_px)
            length = np.concatenate([[0.0], np.cumsum(steps)])
            for i, j in zip(kept[:-1], kept[1:], strict=False):
                a, b = chain[i], chain[j]
                keep[a] = keep[b] = True
                if a != b:
                    key = (min(a, b), max(a, b))
                    new_edges[key] = min(new_edges.get(key, math.inf), length[j] - length[i])
    ids = np.nonzero(keep)[0]
    new_id = np.full(n, -1, np.int64)
    new_id[ids] = np.arange(ids.size)
    pairs = np.array(list(new_edges), np.int64).reshape(-1, 2)
    return ids, new_id[pairs], np.array(list(new_edges.values()), float)


def _walk(adjacency, degree, start: int, first: int):
    """Nodes from ``start`` through ``first`` along degree-2 nodes to the next other node."""
    chain, steps = [start, first], [adjacency[start][first]]
    prev, cur = start, first
    while degree[cur] == 2 and cur != start:
        nxt = [v for v in adjacency[cur] if v != prev]
        if not nxt:
            break
        prev, cur = cur, nxt[0]
        chain.append(cur)
        steps.append(adjacency[prev][cur])
    return chain, steps
