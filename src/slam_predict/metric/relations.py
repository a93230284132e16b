"""Kümmerle relations: pose pairs (i earlier than j) and their errors.

For a pair (i, j): δ = x_j ⊖ x_i on the estimate and δ* on the reference; the error transform is
e = δ ⊖ δ* (δ expressed in the frame of δ*, i.e. evo's E = δ*⁻¹·δ). Its translational part is
|e_xy| (m) and its rotational part |wrap(e_θ)| (rad). Pair selectors return an (N, 2) int array.
"""
from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

import numpy as np

from slam_predict.geometry import ominus, wrap_angle


class PairSelection(Enum):
    """How pose pairs are chosen."""

    RANDOM = "random"            # n random forward pairs (seeded)
    ALL = "all"                  # every forward pair i < j (exact, O(N²))
    CONSECUTIVE = "consecutive"  # (i, i + delta) for every i (evo --all_pairs, frames)
    AUTO = "auto"                # thesis: pilot of 500, then the sample size for the margins


@dataclass
class RelationErrors:
    """Per-pair errors: ``trans`` (m) and ``rot`` (rad, ≥ 0), both of shape (N,)."""

    trans: np.ndarray
    rot: np.ndarray

    def __len__(self) -> int:
        return len(self.trans)


def relation_deltas(poses: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    """δ_ij = x_j ⊖ x_i for each (i, j) row of ``pairs``; shape (N, 3)."""
    poses = np.asarray(poses, dtype=float)
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    return ominus(poses[pairs[:, 1]], poses[pairs[:, 0]])


def delta_errors(est_deltas: np.ndarray, ref_deltas: np.ndarray) -> RelationErrors:
    """Errors of estimated relations against reference relations, both (N, 3)."""
    err = ominus(np.asarray(est_deltas, float).reshape(-1, 3),
                 np.asarray(ref_deltas, float).reshape(-1, 3))
    return RelationErrors(np.hypot(err[:, 0], err[:, 1]), np.abs(wrap_angle(err[:, 2])))


def relation_errors(est_poses: np.ndarray, ref_poses: np.ndarray,
                    pairs: np.ndarray) -> RelationErrors:
    """Errors of the relations ``pairs`` between two index-aligned trajectories (N, 3)."""
    est_poses = np.asarray(est_poses, dtype=float).reshape(-1, 3)
    ref_poses = np.asarray(ref_poses, dtype=float).reshape(-1, 3)
    if len(est_poses) != len(ref_poses):
        raise ValueError(f"trajectories differ in length: {len(est_poses)} vs {len(ref_poses)}")
    return delta_errors(relation_deltas(est_poses, pairs), relation_deltas(ref_poses, pairs))


def random_forward_pairs(n_poses: int, n_pairs: int, rng: np.random.Generator) -> np.ndarray:
    """``n_pairs`` random pairs (i, j), i < j, drawn uniformly among all forward pairs.

    Draws two distinct indices per pair and orders them (so pairs may repeat across draws).
    """
    if n_poses < 2:
        raise ValueError(f"need at least 2 poses for a relation, got {n_poses}")
    first = rng.integers(0, n_poses, size=n_pairs)
    second = rng.integers(0, n_poses - 1, size=n_pairs)
    second = second + (second >= first)            # uniform over the other n − 1 indices
    return np.column_stack([np.minimum(first, second), np.maximum(first, second)])


def consecutive_pairs(n_poses: int, delta: int = 1) -> np.ndarray:
    """(i, i + delta) for every i (evo's ``--all_pairs`` with a frame delta)."""
    if delta < 1:
        raise ValueError("delta must be ≥ 1")
    i = np.arange(max(n_poses - delta, 0))
    return np.column_stack([i, i + delta])


def count_forward_pairs(n_poses: int) -> int:
    """Number of pairs i < j among ``n_poses`` poses."""
    return n_poses * (n_poses - 1) // 2
