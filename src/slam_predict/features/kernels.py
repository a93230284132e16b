"""numba kernels of the Voronoi traversal: line of sight, shortest paths, the traversal loop.

Conventions: pixels are (row, col) with row 0 at the top of the bitmap; headings are in the
world frame (x right, y up), so the heading of a step (dr, dc) is ``atan2(-dr, dc)`` rad.
Graphs are undirected, in CSR form (``indptr``, ``indices``, ``weights``), each edge stored in
both directions. :func:`warmup` also compiles :mod:`graph_kernels` and :mod:`raster_kernels`.

The *digital line* from pixel a to pixel b (used for line of sight) is defined as: n = max(|Δr|,
|Δc|) steps; step i = 1..n visits (r_a + rnd(Δr·i/n), c_a + rnd(Δc·i/n)) with rnd = round half
up (floor(x + 0.5)). Pixel a itself is not visited, pixel b is.
"""
from __future__ import annotations

import heapq
import math

import numba
import numpy as np

INF = np.inf


@numba.njit(cache=True)
def _rnd(x: float) -> int:
    return int(math.floor(x + 0.5))


@numba.njit(cache=True)
def line_is_free(occupied, r0, c0, r1, c1) -> bool:
    """True when no pixel of the digital line from (r0, c0) (excluded) to (r1, c1) is occupied."""
    dr = r1 - r0
    dc = c1 - c0
    n = max(abs(dr), abs(dc))
    for i in range(1, n + 1):
        r = r0 + _rnd(dr * i / n)
        c = c0 + _rnd(dc * i / n)
        if occupied[r, c]:
            return False
    return True


@numba.njit(cache=True)
def wrap(angle: float) -> float:
    """Angle wrapped to (-pi, pi] (rad)."""
    return math.atan2(math.sin(angle), math.cos(angle))


@numba.njit(cache=True)
def line_is_free_fast(occupied, clearance, r0, c0, r1, c1) -> bool:
    """Same answer as :func:`line_is_free`, skipping steps that clearance guarantees free.

    ``clearance[r, c]`` is the Euclidean distance (px) from pixel (r, c) to the nearest
    occupied pixel centre. Pixels of the digital line lie within 0.5 px (minor axis) of the
    true line, so from step i every step j with (j − i)·step + 1 < clearance(p_i) is free.
    """
    dr = r1 - r0
    dc = c1 - c0
    n = max(abs(dr), abs(dc))
    if n == 0:
        return True
    step = math.sqrt(dr * dr + dc * dc) / n
    i = 1
    while i <= n:
        r = r0 + _rnd(dr * i / n)
        c = c0 + _rnd(dc * i / n)
        if occupied[r, c]:
            return False
        skip = int((clearance[r, c] - 1.0 - 1e-6) / step)
        i += max(skip, 1)
    return True


@numba.njit(cache=True)
def map_phase(occupied, clearance, node_r, node_c, seen, r0, c0, heading, range_px,
              half_fov) -> int:
    """Mark as seen every unseen node visible from (r0, c0) facing ``heading`` (rad).

    Visible = Euclidean distance < ``range_px``, |bearing − heading| ≤ ``half_fov`` and a free
    digital line of sight. Returns the number of newly seen nodes.
    """
    count = 0
    range2 = range_px * range_px
    for k in range(node_r.shape[0]):
        if seen[k]:
            continue
        dr = node_r[k] - r0
        dc = node_c[k] - c0
        if dr * dr + dc * dc >= range2:
            continue
        if dr != 0 or dc != 0:
            bearing = math.atan2(-dr, dc)
            if abs(wrap(bearing - heading)) > half_fov:
                continue
        if line_is_free_fast(occupied, clearance, r0, c0, node_r[k], node_c[k]):
            seen[k] = True
            count += 1
    return count


@numba.njit(cache=True)
def nearest_unseen(node_r, node_c, seen, r0, c0) -> int:
    """Index of the unseen node nearest (Euclidean) to (r0, c0); ties: lowest index; -1: none."""
    best = -1
    best_d = INF
    for k in range(node_r.shape[0]):
        if seen[k]:
            continue
        dr = node_r[k] - r0
        dc = node_c[k] - c0
        d = dr * dr + dc * dc
        if d < best_d:
            best_d = d
            best = k
    return best


@numba.njit(cache=True)
def dijkstra_path(indptr, indices, weights, src, dst):
    """Nodes of a minimum-weight path src → dst (inclusive); empty when unreachable."""
    n = indptr.shape[0] - 1
    dist = np.full(n, INF)
    pred = np.full(n, -1, dtype=np.int64)
    done = np.zeros(n, dtype=np.bool_)
    dist[src] = 0.0
    heap = [(0.0, src)]
    while len(heap) > 0:
        d, u = heapq.heappop(heap)
        if done[u]:
            continue
        done[u] = True
        if u == dst:
            break
        for j in range(indptr[u], indptr[u + 1]):
            v = indices[j]
            nd = d + weights[j]
            if nd < dist[v]:
                dist[v] = nd
                pred[v] = u
                heapq.heappush(heap, (nd, v))
    return _unwind(pred, src, dst)


@numba.njit(cache=True)
def bfs_path(indptr, indices, src, dst):
    """Nodes of a fewest-hops path src → dst (inclusive), or an empty array when unreachable."""
    n = indptr.shape[0] - 1
    pred = np.full(n, -1, dtype=np.int64)
    visited = np.zeros(n, dtype=np.bool_)
    queue = np.empty(n, dtype=np.int64)
    head, tail = 0, 1
    queue[0] = src
    visited[src] = True
    while head < tail:
        u = queue[head]
        head += 1
        if u == dst:
            break
        for j in range(indptr[u], indptr[u + 1]):
            v = indices[j]
            if not visited[v]:
                visited[v] = True
                pred[v] = u
                queue[tail] = v
                tail += 1
    return _unwind(pred, src, dst)


@numba.njit(cache=True)
def _unwind(pred, src, dst):
    if src == dst:
        out = np.empty(1, dtype=np.int64)
        out[0] = src
        return out
    if pred[dst] < 0:
        return np.empty(0, dtype=np.int64)
    length = 1
    v = dst
    while v != src:
        v = pred[v]
        length += 1
    out = np.empty(length, dtype=np.int64)
    v = dst
    for i in range(length - 1, -1, -1):
        out[i] = v
        v = pred[v]
    return out


@numba.njit(cache=True)
def traverse(occupied, clearance, node_r, node_c, indptr, indices, weights, start, heading0,
             angle0, range_px, half_fov, min_rot_px, use_hops, reset_heading):
    """Voronoi traversal (Algorithms 3–4 of the seed thesis) on a graph of pixel nodes.

    Mapping at the start node, then repeatedly: nearest unseen node (Euclidean), shortest path
    (Dijkstra on ``weights``, or fewest hops when ``use_hops``), and at every node of the path a
    step (distance and rotation bookkeeping) followed by a mapping phase. The rotation is
    counted between anchor points whose path distance exceeds ``min_rot_px``.

    ``heading0`` is the initial sensor heading and ``angle0`` the initial reference of the
    rotation count (rad). ``reset_heading`` reproduces the seed code: a scan taken without
    moving (the first node of each path) faces heading 0 instead of keeping the last heading.

    Returns (visited node sequence, distance px, rotation rad, number of mapping phases).
    """
    n = node_r.shape[0]
    seen = np.zeros(n, dtype=np.bool_)
    cur = start
    heading = heading0
    robot_angle = angle0
    anchor = cur
    partial = 0.0
    total = 0.0
    rotation = 0.0
    visits = [cur]
    n_seen = map_phase(occupied, clearance, node_r, node_c, seen, node_r[cur], node_c[cur],
                       heading, range_px, half_fov)
    scans = 1
    while n_seen < n:
        target = nearest_unseen(node_r, node_c, seen, node_r[cur], node_c[cur])
        if use_hops:
            path = bfs_path(indptr, indices, cur, target)
        else:
            path = dijkstra_path(indptr, indices, weights, cur, target)
        if path.shape[0] == 0:  # unreachable (cannot happen on a connected graph)
            seen[target] = True
            n_seen += 1
            continue
        for i in range(path.shape[0]):
            nxt = path[i]
            dr = node_r[nxt] - node_r[cur]
            dc = node_c[nxt] - node_c[cur]
            step = math.sqrt(dr * dr + dc * dc)
            total += step
            partial += step
            if partial > min_rot_px:
                chord = math.atan2(-(node_r[nxt] - node_r[anchor]), node_c[nxt] - node_c[anchor])
                rotation += abs(wrap(chord - robot_angle))
                robot_angle = chord
                anchor = nxt
                partial = 0.0
            if step > 0.0:
                heading = math.atan2(-dr, dc)
            elif reset_heading:
                heading = 0.0
            cur = nxt
            if nxt != visits[len(visits) - 1]:
                visits.append(nxt)
            n_seen += map_phase(occupied, clearance, node_r, node_c, seen, node_r[cur],
                                node_c[cur], heading, range_px, half_fov)
            scans += 1
        cur = target
    out = np.empty(len(visits), dtype=np.int64)
    for i in range(len(visits)):
        out[i] = visits[i]
    return out, total, rotation, scans


def warmup() -> None:
    """Compile every feature kernel on a tiny input (numba caches the result on disk)."""
    occ = np.zeros((5, 5), dtype=np.bool_)
    node_r = np.array([1, 1, 3], dtype=np.int64)
    node_c = np.array([1, 3, 3], dtype=np.int64)
    indptr = np.array([0, 1, 3, 4], dtype=np.int64)
    indices = np.array([1, 0, 2, 1], dtype=np.int64)
    weights = np.ones(4)
    for hops in (False, True):
        traverse(occ, np.full((5, 5), 9.0), node_r, node_c, indptr, indices, weights, 0, 0.0,
                 0.0, 10.0, 2.0, 1.0, hops, hops)
    line_is_free(occ, 0, 0, 4, 3)
    from slam_predict.features import graph_kernels, raster_kernels

    graph_kernels.warmup()
    raster_kernels.warmup()
