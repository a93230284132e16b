"""openslam_gmapping's own random stream: POSIX ``drand48`` and its ``pf_ran_gaussian``.

The real library draws every motion-model noise sample with ``pf_ran_gaussian`` (utils/stat.cpp)
and every resampling offset with ``drand48()``; slam_gmapping seeds the stream once with
``sampleGaussian(1, seed)``, i.e. ``srand48(seed)`` followed by one discarded Gaussian draw.
:class:`Drand48Generator` reproduces that stream exactly and offers the two numpy ``Generator``
methods the filter calls (``standard_normal``, ``random``). Our motion model draws particle by
particle, x, y, θ, skipping zero-σ components (as upstream's ``sampleGaussian`` returns 0
without drawing for σ = 0), so with this generator our port draws the same numbers in the same
order as the real library.

drand48: the 48-bit linear congruential generator x ← (a·x + c) mod 2⁴⁸ with a = 0x5DEECE66D,
c = 0xB, value x / 2⁴⁸ ∈ [0, 1). ``srand48(s)`` sets x = (low 32 bits of s) · 2¹⁶ + 0x330E.
``sampleGaussian`` does not seed when its seed is 0: the stream then starts from drand48's
initial state (that of ``srand48(0x1234ABCD)``), which :class:`Drand48Generator` (seed 0) keeps.

pf_ran_gaussian (polar Box–Muller): per attempt, u₁ (redrawn while 0), then one draw that is
only checked for 0 (redrawn while 0) and discarded, then u₂ (not checked); x₁ = 2u₁ − 1,
x₂ = 2u₂ − 1, w = x₁² + x₂²; retried while w > 1 or w = 0; result x₂·√(−2 ln w / w).
The discarded draw is upstream's behaviour and is kept: it is part of the stream.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from slam_predict.slam.gmapping.params import SEED_MAX, STREAMS

A = np.uint64(0x5DEECE66D)
C = np.uint64(0xB)
MASK = np.uint64((1 << 48) - 1)
SCALE = 1.0 / float(1 << 48)
SEED_LOW = np.uint64(0x330E)
UNSEEDED_STATE = 0x1234ABCD330E   # drand48's state before any srand48


def seeded_state(seed: int) -> int:
    """The 48-bit drand48 state after ``sampleGaussian``'s seeding with ``seed`` (before its
    first draw): ``srand48(seed)``, or the initial state for seed 0 (upstream skips srand48)."""
    seed = int(seed)
    if seed == 0:
        return UNSEEDED_STATE
    return ((seed & 0xFFFFFFFF) << 16) | 0x330E


@njit(cache=True)
def _drand48(state):
    """Advance ``state`` (uint64[1], 48-bit) by one step; the new value in [0, 1)."""
    x = (A * state[0] + C) & MASK
    state[0] = x
    return float(x) * SCALE


@njit(cache=True)
def _gaussian(state):
    """One pf_ran_gaussian(1) draw from ``state`` (see the module docstring)."""
    while True:
        r = _drand48(state)
        while r == 0.0:
            r = _drand48(state)
        x1 = 2.0 * r - 1.0
        r = _drand48(state)
        while r == 0.0:
            r = _drand48(state)
        x2 = 2.0 * _drand48(state) - 1.0
        w = x1 * x1 + x2 * x2
        if not (w > 1.0 or w == 0.0):
            return x2 * math.sqrt(-2.0 * math.log(w) / w)


@njit(cache=True)
def _fill_gaussian(state, out):
    """Fill the 1-D ``out`` with consecutive pf_ran_gaussian(1) draws."""
    for i in range(out.size):
        out[i] = _gaussian(state)


@njit(cache=True)
def _fill_uniform(state, out):
    """Fill the 1-D ``out`` with consecutive drand48 draws."""
    for i in range(out.size):
        out[i] = _drand48(state)


class Drand48Generator:
    """The real GMapping's random stream behind the numpy ``Generator`` methods our filter calls.

    ``seed`` (0 ≤ seed ≤ 2³² − 1) is the seed slam_gmapping passes to ``sampleGaussian(1,
    seed)``; construction performs that call's draw, as the node does at start-up.
    """

    def __init__(self, seed: int):
        seed = int(seed)
        if not 0 <= seed <= SEED_MAX:
            raise ValueError(f"drand48 seed must be in [0, {SEED_MAX}], got {seed}")
        self.seed = seed
        self.state = np.array([seeded_state(seed)], dtype=np.uint64)
        self.standard_normal(1)

    def standard_normal(self, shape) -> np.ndarray:
        """Standard normal samples (pf_ran_gaussian(1)), drawn in C order into ``shape``."""
        out = np.empty(shape, dtype=np.float64)
        _fill_gaussian(self.state, out.reshape(-1))
        return out

    def random(self, size=None):
        """drand48() values in [0, 1): one float (``size`` None) or an array of ``size``."""
        out = np.empty(1 if size is None else size, dtype=np.float64)
        _fill_uniform(self.state, out.reshape(-1))
        return float(out[0]) if size is None else out


def noise_generator(stream: str, drand48_seed: int | None, rng: np.random.Generator):
    """(the generator the filter draws from, the drand48 seed used or None) for the GMapping
    parameters ``random_stream`` / ``drand48_seed`` and the run's numpy generator ``rng``.

    ``numpy``: ``rng`` itself. ``drand48``: a :class:`Drand48Generator` seeded with
    ``drand48_seed``, or when that is None with ``int(rng.integers(1, 2**31 - 1))`` (so a run
    stays determined by the seed of ``rng``).
    """
    if stream == "numpy":
        return rng, None
    if stream != "drand48":
        raise ValueError(f"random_stream must be one of {', '.join(STREAMS)}, got {stream!r}")
    seed = int(rng.integers(1, 2 ** 31 - 1)) if drand48_seed is None else int(drand48_seed)
    return Drand48Generator(seed), seed


def warmup() -> None:
    """Compile (or load from the numba cache) the generator's kernels."""
    Drand48Generator(1).standard_normal((2, 3))
    Drand48Generator(1).random(2)
