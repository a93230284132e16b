"""numba kernels on graphs: the seed's pass-through removal and the all-pairs hop sweep.

Graphs are undirected; CSR arrays (``indptr``, ``indices``) store each edge in both directions.
"""
from __future__ import annotations

import math

import numba
import numpy as np


@numba.njit(cache=True)
def _rnd(x: float) -> int:
    return int(math.floor(x + 0.5))


@numba.njit(cache=True)
def remove_pass_through(nbr, wgt, node_r, node_c, skeleton, align_px, order):
    """Remove pass-through nodes in place (the seed's sparsification), in the given node order.

    ``nbr`` (N, K) holds neighbour ids (−1 = empty slot) and ``wgt`` the edge weights. A node
    with exactly two neighbours n1, n2 is removed when the skeleton continues straight beyond
    both: a skeleton pixel lies in the 3×3 window centred ``align_px`` beyond n2 along n1→n2,
    and in the one ``align_px`` before n1. n1 and n2 are then joined with the summed weight
    (keeping the lighter edge when they were already adjacent). Returns the alive mask.
    """
    n = nbr.shape[0]
    alive = np.ones(n, dtype=np.bool_)
    rows, cols = skeleton.shape
    for idx in range(order.shape[0]):
        u = order[idx]
        a = -1
        b = -1
        wa = 0.0
        wb = 0.0
        deg = 0
        for j in range(nbr.shape[1]):
            if nbr[u, j] >= 0:
                deg += 1
                if a < 0:
                    a = nbr[u, j]
                    wa = wgt[u, j]
                else:
                    b = nbr[u, j]
                    wb = wgt[u, j]
        if deg != 2:
            continue
        dr = float(node_r[b] - node_r[a])
        dc = float(node_c[b] - node_c[a])
        norm = math.sqrt(dr * dr + dc * dc)
        if norm == 0.0:
            continue
        ur = dr / norm * align_px
        uc = dc / norm * align_px
        if not _window_hit(skeleton, node_r[b] + ur, node_c[b] + uc, rows, cols):
            continue
        if not _window_hit(skeleton, node_r[a] - ur, node_c[a] - uc, rows, cols):
            continue
        _merge(nbr, wgt, alive, u, a, b, wa + wb)
    return alive


@numba.njit(cache=True)
def _merge(nbr, wgt, alive, u, a, b, w):
    _unlink(nbr, a, u)
    _unlink(nbr, b, u)
    alive[u] = False
    for j in range(nbr.shape[1]):
        nbr[u, j] = -1
    _link(nbr, wgt, a, b, w)
    _link(nbr, wgt, b, a, w)


@numba.njit(cache=True)
def _window_hit(skeleton, r, c, rows, cols) -> bool:
    rr = _rnd(r)
    cc = _rnd(c)
    for i in range(rr - 1, rr + 2):
        for j in range(cc - 1, cc + 2):
            if 0 <= i < rows and 0 <= j < cols and skeleton[i, j]:
                return True
    return False


@numba.njit(cache=True)
def _unlink(nbr, u, v):
    for j in range(nbr.shape[1]):
        if nbr[u, j] == v:
            nbr[u, j] = -1


@numba.njit(cache=True)
def _link(nbr, wgt, u, v, w):
    free = -1
    for j in range(nbr.shape[1]):
        if nbr[u, j] == v:
            if w < wgt[u, j]:
                wgt[u, j] = w
            return
        if nbr[u, j] < 0 and free < 0:
            free = j
    nbr[u, free] = v
    wgt[u, free] = w


@numba.njit(cache=True)
def all_pairs_hops(indptr, indices):
    """Unweighted all-pairs sweep: eccentricity, sum of hop distances, betweenness (raw).

    One BFS per source (Brandes' accumulation); betweenness is summed over ordered pairs, so
    networkx's normalised value is ``raw / ((n − 1)(n − 2))``. Assumes a connected graph.
    """
    n = indptr.shape[0] - 1
    ecc = np.zeros(n, dtype=np.int64)
    dsum = np.zeros(n, dtype=np.float64)
    between = np.zeros(n, dtype=np.float64)
    dist = np.empty(n, dtype=np.int64)
    sigma = np.empty(n, dtype=np.float64)
    delta = np.empty(n, dtype=np.float64)
    order = np.empty(n, dtype=np.int64)
    for s in range(n):
        dist[:] = -1
        sigma[:] = 0.0
        delta[:] = 0.0
        dist[s] = 0
        sigma[s] = 1.0
        order[0] = s
        head, tail = 0, 1
        while head < tail:
            u = order[head]
            head += 1
            for j in range(indptr[u], indptr[u + 1]):
                v = indices[j]
                if dist[v] < 0:
                    dist[v] = dist[u] + 1
                    order[tail] = v
                    tail += 1
                if dist[v] == dist[u] + 1:
                    sigma[v] += sigma[u]
        total = 0
        for i in range(tail):
            total += dist[order[i]]
        ecc[s] = dist[order[tail - 1]]
        dsum[s] = total
        for i in range(tail - 1, -1, -1):
            w = order[i]
            for j in range(indptr[w], indptr[w + 1]):
                v = indices[j]
                if dist[v] == dist[w] - 1:
                    delta[v] += sigma[v] / sigma[w] * (1.0 + delta[w])
            if w != s:
                between[w] += delta[w]
    return ecc, dsum, between


@numba.njit(cache=True)
def critical_candidates(indptr, indices, weights, dist, max_half_px, radius_px, side_px,
                        widen_px, widen_ratio):
    """Doorway candidates on a skeleton graph (room segmentation, :mod:`rooms`).

    Node p qualifies when it has two neighbours, ``dist[p]`` ≤ ``max_half_px``, no node
    within ``radius_px`` along the skeleton on either side has a smaller clearance, and each
    side reaches a clearance ≥ dist[p] + max(``widen_px``, ``widen_ratio``·dist[p]) within
    ``side_px``. Returns the candidate node indices.
    """
    n = indptr.shape[0] - 1
    out = []
    best = np.full(n, np.inf)
    for p in range(n):
        if indptr[p + 1] - indptr[p] != 2 or dist[p] > max_half_px:
            continue
        need = dist[p] + max(widen_px, widen_ratio * dist[p])
        ok = True
        for side in range(2):
            first = indices[indptr[p] + side]
            low, high = _side_extremes(indptr, indices, weights, dist, p, first,
                                       weights[indptr[p] + side], radius_px, side_px, best)
            if low < dist[p] or high < need:
                ok = False
                break
        if ok:
            out.append(p)
    return np.array(out, dtype=np.int64)


@numba.njit(cache=True)
def _side_extremes(indptr, indices, weights, dist, p, first, w0, radius_px, side_px, best):
    """Min clearance within ``radius_px`` and max within ``side_px`` on one side of ``p``."""
    low = np.inf
    high = -np.inf
    stack = [(first, w0)]
    touched = [first]
    best[first] = w0
    while len(stack) > 0:
        u, d = stack.pop()
        if d > best[u]:
            continue
        if d <= radius_px and dist[u] < low:
            low = dist[u]
        if dist[u] > high:
            high = dist[u]
        for j in range(indptr[u], indptr[u + 1]):
            v = indices[j]
            nd = d + weights[j]
            if v == p or nd > side_px or nd >= best[v]:
                continue
            if best[v] == np.inf:
                touched.append(v)
            best[v] = nd
            stack.append((v, nd))
    for u in touched:
        best[u] = np.inf
    return low, high



@numba.njit(cache=True)
def suppress_neighbours(rr, cc, dist, order, factor):
    """Greedy non-maximum suppression: walk ``order`` (best first) and keep a point unless a
    kept one lies within ``factor`` × max(dist of both) (px). Returns the kept indices."""
    kept = []
    for k in order:
        ok = True
        for j in kept:
            reach = factor * max(dist[k], dist[j])
            if (rr[k] - rr[j]) ** 2 + (cc[k] - cc[j]) ** 2 <= reach * reach:
                ok = False
                break
        if ok:
            kept.append(k)
    return np.array(kept, dtype=np.int64)


def warmup() -> None:
    """Compile the kernels on a tiny graph."""
    node_r = np.array([1, 1, 3], dtype=np.int64)
    node_c = np.array([1, 3, 3], dtype=np.int64)
    indptr = np.array([0, 1, 3, 4], dtype=np.int64)
    indices = np.array([1, 0, 2, 1], dtype=np.int64)
    all_pairs_hops(indptr, indices)
    found = critical_candidates(indptr, indices, np.ones(4), np.array([3.0, 1.0, 3.0]), 2.0,
                                1.0, 3.0, 0.5, 0.2)
    suppress_neighbours(node_r, node_c, np.ones(3), found, 2.0)
    nbr = np.array([[1, -1], [0, 2], [1, -1]], dtype=np.int64)
    remove_pass_through(nbr, np.ones((3, 2)), node_r, node_c, np.zeros((5, 5), np.bool_), 1.0,
                        np.arange(3, dtype=np.int64))
