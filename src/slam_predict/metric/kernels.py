"""numba kernel: statistics of the relation errors over every forward pair i < j.

Exact thesis eq. 3.1 over all N(N−1)/2 relations without materialising them. For a pair,
|trans(δ ⊖ δ*)| = |Δ_est − Δ_ref| where Δ is pose j's position in pose i's frame (the final
rotation by −θ(δ*) preserves the norm), and rot = |wrap(Δθ_est − Δθ_ref)|. Each row i is reduced
in two passes (mean, then squared deviations) and merged into the totals with Chan et al.'s
pairwise update, so the result is as accurate as a two-pass computation over all pairs.
"""
from __future__ import annotations

import math

import numba
import numpy as np

# Columns of the moments array: count, mean, M2 (sum of squared deviations), min, max,
# sum of squares.
N_, MEAN, M2, MIN, MAX, SUMSQ = range(6)
SERIES = ("trans_abs", "trans_sqr", "rot_abs", "rot_sqr")


@numba.njit(cache=True)
def _row_errors(est, ref, i, trans, rot):
    n = est.shape[0]
    ce, se = math.cos(est[i, 2]), math.sin(est[i, 2])
    cr, sr = math.cos(ref[i, 2]), math.sin(ref[i, 2])
    for k in range(n - i - 1):
        j = i + 1 + k
        dxe, dye = est[j, 0] - est[i, 0], est[j, 1] - est[i, 1]
        dxr, dyr = ref[j, 0] - ref[i, 0], ref[j, 1] - ref[i, 1]
        ex = (ce * dxe + se * dye) - (cr * dxr + sr * dyr)
        ey = (-se * dxe + ce * dye) - (-sr * dxr + cr * dyr)
        trans[k] = math.sqrt(ex * ex + ey * ey)
        a = (est[j, 2] - est[i, 2]) - (ref[j, 2] - ref[i, 2])
        a = (a + math.pi) % (2.0 * math.pi) - math.pi
        rot[k] = abs(a)


@numba.njit(cache=True)
def _merge(moments, s, values, m, squared):
    total = 0.0
    lo, hi, sumsq = np.inf, -np.inf, 0.0
    for k in range(m):
        v = values[k] * values[k] if squared else values[k]
        total += v
        sumsq += v * v
        lo = min(lo, v)
        hi = max(hi, v)
    mean_b = total / m
    m2_b = 0.0
    for k in range(m):
        v = values[k] * values[k] if squared else values[k]
        m2_b += (v - mean_b) * (v - mean_b)
    n_a = moments[s, N_]
    n = n_a + m
    delta = mean_b - moments[s, MEAN]
    moments[s, MEAN] += delta * m / n
    moments[s, M2] += m2_b + delta * delta * n_a * m / n
    moments[s, N_] = n
    moments[s, MIN] = min(moments[s, MIN], lo)
    moments[s, MAX] = max(moments[s, MAX], hi)
    moments[s, SUMSQ] += sumsq


@numba.njit(cache=True)
def all_pairs_moments(est, ref):
    """Moments (4 series × 6 columns, see module constants) over every pair i < j."""
    n = est.shape[0]
    moments = np.zeros((4, 6))
    for s in range(4):
        moments[s, MIN] = np.inf
        moments[s, MAX] = -np.inf
    trans = np.empty(max(n - 1, 1))
    rot = np.empty(max(n - 1, 1))
    for i in range(n - 1):
        m = n - i - 1
        _row_errors(est, ref, i, trans, rot)
        _merge(moments, 0, trans, m, False)
        _merge(moments, 1, trans, m, True)
        _merge(moments, 2, rot, m, False)
        _merge(moments, 3, rot, m, True)
    return moments


def warmup() -> None:
    """Compile the kernels on a tiny input."""
    poses = np.zeros((3, 3))
    all_pairs_moments(poses, poses)
