"""The real GMapping's random stream for our port: POSIX drand48 and openslam_gmapping's
``pf_ran_gaussian`` (polar Box-Muller, three drand48 draws per attempt), seeded as slam_gmapping
seeds it (``sampleGaussian(1, seed)``: srand48(seed), then one draw discarded).

:class:`Drand48Generator` offers the two methods our filter uses (``standard_normal``,
``random``) and draws in the same order as upstream (particle by particle, x, y, θ; zero-σ
components skipped), so with it our port replays the real library's noise exactly.
"""
from __future__ import annotations

import math

import numpy as np

_A, _C, _MASK = 0x5DEECE66D, 0xB, (1 << 48) - 1


class Drand48Generator:
    """drand48 / pf_ran_gaussian with the numpy Generator methods the GMapping port calls."""

    def __init__(self, seed: int):
        self.state = ((int(seed) & 0xFFFFFFFF) << 16) | 0x330E  # srand48
        self.gaussian()  # sampleGaussian(1, seed) draws once after seeding

    def drand48(self) -> float:
        self.state = (_A * self.state + _C) & _MASK
        return self.state / float(1 << 48)

    def gaussian(self) -> float:
        """pf_ran_gaussian(1)."""
        while True:
            r = self.drand48()
            while r == 0.0:
                r = self.drand48()
            x1 = 2.0 * r - 1.0
            r = self.drand48()
            while r == 0.0:
                r = self.drand48()
            x2 = 2.0 * self.drand48() - 1.0
            w = x1 * x1 + x2 * x2
            if not (w > 1.0 or w == 0.0):
                return x2 * math.sqrt(-2.0 * math.log(w) / w)

    def standard_normal(self, shape) -> np.ndarray:
        out = np.empty(shape)
        flat = out.reshape(-1)
        for i in range(flat.size):
            flat[i] = self.gaussian()
        return out

    def random(self) -> float:
        return self.drand48()
