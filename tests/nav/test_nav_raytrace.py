"""The obstacle layer's clearing ray (costmap_2d raytraceLine) against a closed-form Bresenham
line: after i steps along the dominant axis the other axis has moved floor((a//2 + i·b) / a)
cells, where a and b are the dominant and the other axis' lengths in cells."""
from __future__ import annotations

import math

import numpy as np

from slam_predict.nav.kernels import _bresenham_mark


def reference_cells(x0: int, y0: int, x1: int, y1: int, max_len: float) -> set[tuple[int, int]]:
    """Cells (x, y) raytraceLine sets: the steps before the length limit and the cell where
    it stopped."""
    dx, dy = x1 - x0, y1 - y0
    x_major = abs(dx) >= abs(dy)
    a, b = (abs(dx), abs(dy)) if x_major else (abs(dy), abs(dx))
    dist = math.hypot(dx, dy)
    scale = 1.0 if dist == 0.0 else min(1.0, max_len / dist)
    steps = min(int(scale * a), a)
    sx, sy = int(np.sign(dx)), int(np.sign(dy))
    cells = set()
    for i in range(steps + 1):
        minor = (a // 2 + i * b) // a if a else 0
        major = i
        cells.add((x0 + sx * major, y0 + sy * minor) if x_major
                  else (x0 + sx * minor, y0 + sy * major))
    return cells


def test_clearing_ray_matches_the_closed_form_line_on_random_rays():
    rng = np.random.default_rng(7)
    shape = (60, 80)
    for _ in range(400):
        x0, y0 = int(rng.integers(0, shape[1])), int(rng.integers(0, shape[0]))
        x1, y1 = int(rng.integers(-20, shape[1] + 20)), int(rng.integers(-20, shape[0] + 20))
        max_len = float(rng.choice([5.0, 30.0, 1e9]))
        grid = np.zeros(shape, np.uint8)
        _bresenham_mark(grid, x0, y0, x1, y1, max_len, 7)
        expected = {(x, y) for x, y in reference_cells(x0, y0, x1, y1, max_len)
                    if 0 <= x < shape[1] and 0 <= y < shape[0]}
        ys, xs = np.nonzero(grid)
        marked = set(zip(xs.tolist(), ys.tolist(), strict=True))
        assert marked == expected, (x0, y0, x1, y1, max_len)
