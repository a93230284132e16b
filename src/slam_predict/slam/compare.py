"""Checks of a SLAM result against a reference: rigid trajectory fit and map agreement.

- :func:`rigid_fit`: the SE(2) transform (least squares on positions, Kabsch/Umeyama without
  scale) that best maps an estimated trajectory onto a reference one.
- :func:`map_agreement`: the fraction of the occupied cells of one grid that lie within ``tol``
  cells of an occupied cell of another grid of the same geometry, both ways.
"""
from __future__ import annotations

import numpy as np
from scipy import ndimage

from slam_predict.geometry import compose


def rigid_fit(est: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """Pose (x m, y m, yaw rad) T minimising Σ |T ⊕ est_i.xy − ref_i.xy|² over matched poses."""
    a = np.asarray(est, dtype=float)[:, :2]
    b = np.asarray(ref, dtype=float)[:, :2]
    if len(a) != len(b) or len(a) < 2:
        raise ValueError("need two trajectories of equal length ≥ 2")
    ca, cb = a.mean(axis=0), b.mean(axis=0)
    h = (a - ca).T @ (b - cb)
    yaw = np.arctan2(h[0, 1] - h[1, 0], h[0, 0] + h[1, 1])
    c, s = np.cos(yaw), np.sin(yaw)
    t = cb - np.array([[c, -s], [s, c]]) @ ca
    return np.array([t[0], t[1], yaw])


def apply_transform(transform: np.ndarray, poses: np.ndarray) -> np.ndarray:
    """T ⊕ poses for each pose (N, 3)."""
    return compose(np.asarray(transform, dtype=float), np.asarray(poses, dtype=float))


def map_agreement(a: np.ndarray, b: np.ndarray, tol: float = 2.0,
                  occupied: int = 100) -> tuple[float, float]:
    """(share of a's occupied cells near b's, share of b's near a's); "near" = within ``tol``
    cells (Euclidean). ``a`` and ``b`` are grids of the same shape and geometry."""
    occ_a = np.asarray(a) >= occupied
    occ_b = np.asarray(b) >= occupied
    if occ_a.shape != occ_b.shape:
        raise ValueError(f"grids differ in shape: {occ_a.shape} vs {occ_b.shape}")
    return _near_share(occ_a, occ_b, tol), _near_share(occ_b, occ_a, tol)


def _near_share(src: np.ndarray, dst: np.ndarray, tol: float) -> float:
    if not src.any():
        return float("nan")
    if not dst.any():
        return 0.0
    rows, cols = np.nonzero(src | dst)
    r0, r1 = max(rows.min() - 3, 0), rows.max() + 4
    c0, c1 = max(cols.min() - 3, 0), cols.max() + 4
    dist = ndimage.distance_transform_edt(~dst[r0:r1, c0:c1])
    return float(np.mean(dist[src[r0:r1, c0:c1]] <= tol))
