"""Slow, plain-Python references for the feature kernels (no numba, no shared code).

Each follows the written rule literally; tests compare the fast kernels with them.
"""
from __future__ import annotations

import heapq
import math

import numpy as np


def digital_line(r0: int, c0: int, r1: int, c1: int) -> list[tuple[int, int]]:
    """Pixels of the digital line from (r0, c0) (excluded) to (r1, c1) (included)."""
    n = max(abs(r1 - r0), abs(c1 - c0))
    return [(r0 + math.floor((r1 - r0) * i / n + 0.5), c0 + math.floor((c1 - c0) * i / n + 0.5))
            for i in range(1, n + 1)]


def visible(occupied, a, b) -> bool:
    """No occupied pixel on the digital line a → b."""
    return not any(occupied[r][c] for r, c in digital_line(a[0], a[1], b[0], b[1]))


def adjacency(n: int, edges, weights) -> list[list[tuple[int, float]]]:
    """Sorted neighbour lists (neighbour, weight) of an undirected graph."""
    adj: list[dict[int, float]] = [dict() for _ in range(n)]
    for (a, b), w in zip(edges, weights, strict=False):
        adj[a][b] = w
        adj[b][a] = w
    return [sorted(d.items()) for d in adj]


def dijkstra(adj, src: int, dst: int) -> list[int]:
    """Minimum-weight path; ties: the first improvement found wins, heap pops (dist, node)."""
    dist = {src: 0.0}
    pred = {}
    done = set()
    heap = [(0.0, src)]
    while heap:
        d, u = heapq.heappop(heap)
        if u in done:
            continue
        done.add(u)
        if u == dst:
            break
        for v, w in adj[u]:
            if d + w < dist.get(v, math.inf):
                dist[v] = d + w
                pred[v] = u
                heapq.heappush(heap, (d + w, v))
    return _unwind(pred, src, dst)


def bfs(adj, src: int, dst: int) -> list[int]:
    """Fewest-hops path, neighbours visited in increasing index order."""
    pred = {src: -1}
    queue = [src]
    for u in queue:
        if u == dst:
            break
        for v, _ in adj[u]:
            if v not in pred:
                pred[v] = u
                queue.append(v)
    return _unwind(pred, src, dst)


def _unwind(pred, src, dst) -> list[int]:
    path = [dst]
    while path[-1] != src:
        path.append(pred[path[-1]])
    return path[::-1]


def traverse(occupied, rc, edges, weights, start: int, heading0: float, angle0: float,
             range_px: float, half_fov: float, min_rot_px: float, hops: bool,
             reset_heading: bool):
    """Algorithms 3–4 literally: returns (visited sequence, distance px, rotation rad)."""
    occ = occupied.tolist()
    nodes = [tuple(int(v) for v in p) for p in rc]
    adj = adjacency(len(nodes), edges.tolist(), list(weights))
    seen = [False] * len(nodes)

    def scan(here, heading):
        for k, p in enumerate(nodes):
            if seen[k]:
                continue
            dr, dc = p[0] - here[0], p[1] - here[1]
            if dr * dr + dc * dc >= range_px ** 2:
                continue
            if (dr or dc) and abs(math.remainder(math.atan2(-dr, dc) - heading, 2 * math.pi)
                                  ) > half_fov:
                continue
            if visible(occ, here, p):
                seen[k] = True

    cur, heading, robot_angle, anchor = start, heading0, angle0, start
    partial = total = rotation = 0.0
    visits = [start]
    scan(nodes[cur], heading)
    while not all(seen):
        here = nodes[cur]
        target = min((k for k in range(len(nodes)) if not seen[k]),
                     key=lambda k: ((nodes[k][0] - here[0]) ** 2 + (nodes[k][1] - here[1]) ** 2,
                                    k))
        path = bfs(adj, cur, target) if hops else dijkstra(adj, cur, target)
        for nxt in path:
            dr, dc = nodes[nxt][0] - nodes[cur][0], nodes[nxt][1] - nodes[cur][1]
            step = math.hypot(dr, dc)
            total += step
            partial += step
            if partial > min_rot_px:
                chord = math.atan2(-(nodes[nxt][0] - nodes[anchor][0]),
                                   nodes[nxt][1] - nodes[anchor][1])
                rotation += abs(math.remainder(chord - robot_angle, 2 * math.pi))
                robot_angle, anchor, partial = chord, nxt, 0.0
            if step > 0:
                heading = math.atan2(-dr, dc)
            elif reset_heading:
                heading = 0.0
            cur = nxt
            if nxt != visits[-1]:
                visits.append(nxt)
            scan(nodes[cur], heading)
        cur = target
    return np.array(visits), total, rotation


def guo_hall(mask: np.ndarray) -> np.ndarray:
    """Guo & Hall (1989) parallel thinning, straight from the paper's conditions."""
    img = mask.astype(bool).copy()
    rows, cols = img.shape

    def px(r, c):
        return int(0 <= r < rows and 0 <= c < cols and img[r, c])

    changed = True
    while changed:
        changed = False
        for it in range(2):
            marks = []
            for r, c in zip(*np.nonzero(img), strict=False):
                p2, p3, p4, p5 = px(r - 1, c), px(r - 1, c + 1), px(r, c + 1), px(r + 1, c + 1)
                p6, p7, p8, p9 = px(r + 1, c), px(r + 1, c - 1), px(r, c - 1), px(r - 1, c - 1)
                cross = ((not p2) and (p3 or p4)) + ((not p4) and (p5 or p6)) + \
                    ((not p6) and (p7 or p8)) + ((not p8) and (p9 or p2))
                n1 = (p9 or p2) + (p3 or p4) + (p5 or p6) + (p7 or p8)
                n2 = (p2 or p3) + (p4 or p5) + (p6 or p7) + (p8 or p9)
                m = ((p6 or p7 or not p9) and p8) if it == 0 else ((p2 or p3 or not p5) and p4)
                if cross == 1 and 2 <= min(n1, n2) <= 3 and not m:
                    marks.append((r, c))
            for r, c in marks:
                img[r, c] = False
            changed |= bool(marks)
    return img
