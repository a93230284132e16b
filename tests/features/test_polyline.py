"""Douglas–Peucker (features/polyline.py) against the textbook recursive form."""
from __future__ import annotations

import math

import numpy as np
import pytest

from slam_predict.features.polyline import douglas_peucker


def chord_distance(p, a, b) -> float:
    """Distance from p to the line through a and b (to a when a = b)."""
    (ax, ay), (bx, by), (px, py) = a, b, p
    length = math.hypot(bx - ax, by - ay)
    if length == 0.0:
        return math.hypot(px - ax, py - ay)
    return abs((bx - ax) * (py - ay) - (by - ay) * (px - ax)) / length


def recursive_reference(points, lo, hi, tolerance) -> set[int]:
    if hi - lo < 2:
        return {lo, hi}
    dists = [chord_distance(points[i], points[lo], points[hi]) for i in range(lo + 1, hi)]
    worst = max(range(len(dists)), key=lambda i: (dists[i], -i))
    if dists[worst] <= tolerance:
        return {lo, hi}
    mid = lo + 1 + worst
    return (recursive_reference(points, lo, mid, tolerance)
            | recursive_reference(points, mid, hi, tolerance))


@pytest.mark.parametrize("seed", range(20))
def test_keeps_the_points_of_the_recursive_form(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 60))
    points = np.cumsum(rng.normal(0.0, 1.0, (n, 2)), axis=0)
    points[rng.random(n) < 0.1] = points[0]          # revisits: zero-length chords
    tolerance = float(rng.uniform(0.0, 2.0))
    expected = sorted(recursive_reference([tuple(p) for p in points], 0, n - 1, tolerance))
    assert douglas_peucker(points, tolerance) == expected


def test_straight_line_keeps_its_ends_and_a_corner_its_corner():
    line = np.column_stack([np.arange(6.0), np.zeros(6)])
    assert douglas_peucker(line, 0.01) == [0, 5]
    corner = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [2.0, 1.0], [2.0, 2.0]])
    assert douglas_peucker(corner, 0.1) == [0, 2, 4]
