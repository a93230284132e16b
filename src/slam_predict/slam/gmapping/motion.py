"""GMapping's odometry motion model (openslam_gmapping motionmodel.cpp, drawFromMotion).

The odometry step Δ = p_new ⊖ p_old (dx, dy, dθ in p_old's frame) gets independent Gaussian
noise per component, with standard deviations

    σx = srr·|dx| + str·|dθ| + 0.3·srr·|dy|
    σy = srr·|dy| + str·|dθ| + 0.3·srr·|dx|
    σθ = stt·|dθ| + srt·√(dx² + dy²)

and the noisy step is composed onto each particle. In the code ``str`` maps rotation to
translation noise and ``srt`` translation to rotation noise. Units: m, rad.
"""
from __future__ import annotations

import math

import numpy as np

from slam_predict.geometry import ominus, wrap_angle


def odometry_step(p_new, p_old) -> np.ndarray:
    """Δ = p_new ⊖ p_old: the odometry step in p_old's frame, θ wrapped to [-π, π)."""
    return ominus(np.asarray(p_new, float), np.asarray(p_old, float))


def noise_stds(delta, srr: float, srt: float, str_: float,
               stt: float) -> tuple[float, float, float]:
    """Standard deviations (m, m, rad) of the noise added to the odometry step ``delta``."""
    dx, dy, dth = (abs(float(v)) for v in delta)
    sx = srr * dx + str_ * dth + 0.3 * srr * dy
    sy = srr * dy + str_ * dth + 0.3 * srr * dx
    sth = stt * dth + srt * math.hypot(dx, dy)
    return sx, sy, sth


def draw_from_motion(poses: np.ndarray, p_new, p_old, srr: float, srt: float, str_: float,
                     stt: float, rng: np.random.Generator) -> np.ndarray:
    """Sample new particle poses (N, 3) after the odometry moved from ``p_old`` to ``p_new``.

    Each particle gets its own noisy copy of the step, composed in the particle's frame. A zero
    step (or zero noise) leaves the poses unchanged and draws no random numbers.
    """
    poses = np.asarray(poses, dtype=float).reshape(-1, 3)
    if np.array_equal(np.asarray(p_new, float), np.asarray(p_old, float)):
        return poses.copy()
    delta = odometry_step(p_new, p_old)
    stds = np.array(noise_stds(delta, srr, srt, str_, stt))
    steps = np.broadcast_to(delta, poses.shape).copy()
    active = stds > 0.0
    if np.any(active):
        noise = rng.standard_normal((len(poses), int(active.sum())))
        steps[:, active] += noise * stds[active]
    return compose_steps(poses, steps)


def compose_steps(poses: np.ndarray, steps: np.ndarray) -> np.ndarray:
    """poses ⊕ steps row by row (both (N, 3)); θ wrapped to [-π, π)."""
    c, s = np.cos(poses[:, 2]), np.sin(poses[:, 2])
    out = np.empty_like(poses)
    out[:, 0] = poses[:, 0] + c * steps[:, 0] - s * steps[:, 1]
    out[:, 1] = poses[:, 1] + s * steps[:, 0] + c * steps[:, 1]
    out[:, 2] = wrap_angle(poses[:, 2] + steps[:, 2])
    return out


def travelled(p_new, p_old) -> tuple[float, float]:
    """(|Δxy| m, |Δθ| rad) between consecutive odometry poses, as the update triggers count them.

    The translation is measured in the odometry frame, the rotation wrapped to [-π, π].
    """
    dx = float(p_new[0]) - float(p_old[0])
    dy = float(p_new[1]) - float(p_old[1])
    dth = math.atan2(math.sin(float(p_new[2]) - float(p_old[2])),
                     math.cos(float(p_new[2]) - float(p_old[2])))
    return math.hypot(dx, dy), abs(dth)
