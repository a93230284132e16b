"""Synthetic laser scans for the SLAM tests: exact ray casting against line segments."""
from __future__ import annotations

import numpy as np

# A 10 m x 8 m room with a pillar and an internal wall stub (segments: x0 y0 x1 y1, m).
ROOM = np.array([
    [-5, -4, 5, -4], [5, -4, 5, 4], [5, 4, -5, 4], [-5, 4, -5, -4],
    [1, 1, 2, 1], [2, 1, 2, 2], [2, 2, 1, 2], [1, 2, 1, 1],
    [-3, -4, -3, -1.5], [-2, 2.5, 0.5, 3.2],
], dtype=float)


def cast(pose, angles, segments=ROOM, max_range=30.0) -> np.ndarray:
    """Ranges (m) from laser pose (x, y, θ) along ``angles`` (rad) to the nearest segment;
    ``max_range`` when nothing is hit."""
    x, y, th = pose
    d = np.stack([np.cos(th + angles), np.sin(th + angles)], axis=1)  # (B, 2)
    p = segments[:, :2]
    e = segments[:, 2:] - p                                            # (S, 2)
    w = p - np.array([x, y])                                           # (S, 2)
    den = d[:, None, 0] * e[None, :, 1] - d[:, None, 1] * e[None, :, 0]  # (B, S)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (w[None, :, 0] * e[None, :, 1] - w[None, :, 1] * e[None, :, 0]) / den
        u = (w[None, :, 0] * d[:, None, 1] - w[None, :, 1] * d[:, None, 0]) / den
    ok = (np.abs(den) > 1e-12) & (t > 0) & (u >= 0) & (u <= 1)
    t = np.where(ok, t, np.inf)
    r = t.min(axis=1)
    return np.where(np.isfinite(r) & (r < max_range), r, max_range)
