"""Random planar trajectories for the metric tests (helper module, imported by name)."""
from __future__ import annotations

import numpy as np


def random_walk(rng: np.random.Generator, n: int, step: float = 0.3) -> np.ndarray:
    """A smooth-ish random planar trajectory (N, 3): x, y in m, yaw in rad (wrapped)."""
    yaw = np.cumsum(rng.normal(0.0, 0.2, n))
    dist = rng.uniform(0.0, step, n)
    x = np.cumsum(dist * np.cos(yaw))
    y = np.cumsum(dist * np.sin(yaw))
    return np.column_stack([x, y, (yaw + np.pi) % (2 * np.pi) - np.pi])


def perturbed(rng: np.random.Generator, poses: np.ndarray, sigma=(0.05, 0.05, 0.02)) -> np.ndarray:
    """``poses`` with accumulated noise (a drifting estimate)."""
    noise = np.cumsum(rng.normal(0.0, sigma, size=poses.shape), axis=0)
    out = poses + noise
    out[:, 2] = (out[:, 2] + np.pi) % (2 * np.pi) - np.pi
    return out

