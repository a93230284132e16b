"""SE(2) poses as (x, y, theta) arrays: composition, inverse, relative pose, angle wrapping.

Units: metres and radians. Functions accept a single pose of shape (3,) or a batch (N, 3).
This is the only module that implements these operations.
"""
from __future__ import annotations

import numpy as np


def wrap_angle(angle):
    """Wrap angle(s) in rad to [-pi, pi)."""
    return (np.asarray(angle) + np.pi) % (2.0 * np.pi) - np.pi


def compose(a, b) -> np.ndarray:
    """a ⊕ b: pose b (expressed in a's frame) mapped into a's parent frame."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    c, s = np.cos(a[..., 2]), np.sin(a[..., 2])
    x = a[..., 0] + c * b[..., 0] - s * b[..., 1]
    y = a[..., 1] + s * b[..., 0] + c * b[..., 1]
    th = wrap_angle(a[..., 2] + b[..., 2])
    return _pose_of(x, y, th)


def inverse(a) -> np.ndarray:
    """⊖a: the inverse transform of pose(s) a."""
    a = np.asarray(a, dtype=float)
    c, s = np.cos(a[..., 2]), np.sin(a[..., 2])
    x = -c * a[..., 0] - s * a[..., 1]
    y = s * a[..., 0] - c * a[..., 1]
    return _pose_of(x, y, wrap_angle(-a[..., 2]))


def _pose_of(x, y, th) -> np.ndarray:
    """Stack components into pose(s) (..., 3); one pose without np.stack's overhead."""
    if np.ndim(x) == 0:
        return np.array([x, y, th], dtype=float)
    return np.stack([x, y, th], axis=-1)


def ominus(b, a) -> np.ndarray:
    """b ⊖ a = (⊖a) ⊕ b: pose b expressed in the frame of pose a (Kümmerle's δ = x_j ⊖ x_i)."""
    return compose(inverse(a), b)


def world_T_map(world_pose, map_pose) -> np.ndarray:
    """The map frame's pose in the world frame from one robot pose known in both frames (taken
    at the same instant): world_pose ⊕ map_pose⁻¹ (m, m, rad)."""
    return compose(world_pose, inverse(map_pose))


def transform_points(pose, points) -> np.ndarray:
    """Map points (N, 2) given in the frame of ``pose`` into the parent frame."""
    pose = np.asarray(pose, dtype=float)
    points = np.asarray(points, dtype=float)
    c, s = np.cos(pose[2]), np.sin(pose[2])
    rot = np.array([[c, -s], [s, c]])
    return points @ rot.T + pose[:2]


def yaw_to_quaternion(yaw):
    """Quaternion (qx, qy, qz, qw) of a rotation by ``yaw`` rad about z."""
    yaw = np.asarray(yaw, dtype=float)
    zeros = np.zeros_like(yaw)
    return np.stack([zeros, zeros, np.sin(yaw / 2.0), np.cos(yaw / 2.0)], axis=-1)


def quaternion_to_yaw(qx, qy, qz, qw):
    """Yaw (rad) of a quaternion, i.e. its rotation about z after projecting to the plane."""
    return np.arctan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))
