"""Douglas–Peucker simplification of an open polyline (skeleton edges, robot paths)."""
from __future__ import annotations

import math

import numpy as np


def douglas_peucker(points: np.ndarray, tolerance: float) -> list[int]:
    """Sorted indices of the points of ``points`` (N ≥ 1, 2) that Douglas–Peucker keeps with
    ``tolerance`` (the points' unit): the first and last always, then, recursively, the point
    farthest from its chord while that distance exceeds the tolerance. Iterative; every point is
    compared with its own chord, so a back-and-forth path keeps its turns."""
    keep = {0, len(points) - 1}
    stack = [(0, len(points) - 1)]
    while stack:
        lo, hi = stack.pop()
        if hi - lo < 2:
            continue
        a, b = points[lo], points[hi]
        seg = points[lo + 1:hi]
        ab = b - a
        length = math.hypot(ab[0], ab[1])
        if length == 0.0:
            dist = np.hypot(seg[:, 0] - a[0], seg[:, 1] - a[1])
        else:
            dist = np.abs(ab[0] * (seg[:, 1] - a[1]) - ab[1] * (seg[:, 0] - a[0])) / length
        worst = int(np.argmax(dist))
        if dist[worst] > tolerance:
            mid = lo + 1 + worst
            keep.add(mid)
            stack += [(lo, mid), (mid, hi)]
    return sorted(keep)
