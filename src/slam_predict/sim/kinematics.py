"""Differential-drive kinematics over one simulator step (units m, s, rad).

The commanded velocity is clamped to the velocity bounds and ramped by the acceleration limits,
then held constant for the step (Stage does the same: one velocity per ``interval_sim``). Two
integrators turn it into a body-frame displacement ``(dx, dy, dθ)`` that is composed onto the
pose (``pose ⊕ delta``):

* ``exact``: the arc travelled at constant (v, ω): dx = v·dt·sin(ωdt)/(ωdt),
  dy = v·dt·(1 − cos ωdt)/(ωdt), dθ = ω·dt — exact for piecewise-constant velocity.
* ``stage``: Stage's ``Move()``: translate v·dt along the OLD heading, then rotate by ω·dt,
  i.e. delta = (v·dt, 0, ω·dt) (ros_interfaces.md §1.2–1.3).

Stage's odometry integrates in the other order (rotate first, then translate along the NEW
heading); :func:`rotate_then_translate` implements that update.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from slam_predict.geometry import compose

_SMALL = 1e-4


@dataclass(frozen=True)
class VelocityLimits:
    """Velocity bounds (m/s, rad/s) and acceleration limits (m/s², rad/s²; 0 = unlimited)."""

    max_vel_x: float
    max_vel_theta: float
    max_acc_x: float = 0.0
    max_acc_theta: float = 0.0


def _ramp(target: float, current: float, max_acc: float, dt: float) -> float:
    """Move ``current`` towards ``target`` by at most max_acc·dt (unlimited when max_acc ≤ 0)."""
    if max_acc <= 0.0:
        return target
    step = max_acc * dt
    return current + min(max(target - current, -step), step)


def limit_velocity(v_cmd: float, w_cmd: float, v_prev: float, w_prev: float,
                   limits: VelocityLimits, dt: float) -> tuple[float, float]:
    """The velocity executed this step: command clamped to the bounds, then ramped from the
    previous velocity by the acceleration limits. Returns (v m/s, ω rad/s)."""
    v = min(max(float(v_cmd), -limits.max_vel_x), limits.max_vel_x)
    w = min(max(float(w_cmd), -limits.max_vel_theta), limits.max_vel_theta)
    return _ramp(v, v_prev, limits.max_acc_x, dt), _ramp(w, w_prev, limits.max_acc_theta, dt)


def _sinc(x: float) -> float:
    """sin(x)/x, stable near 0."""
    if abs(x) < _SMALL:
        return 1.0 - x * x / 6.0
    return math.sin(x) / x


def _cosc(x: float) -> float:
    """(1 − cos x)/x, stable near 0 (= sin(x/2)·sinc(x/2))."""
    half = 0.5 * x
    return math.sin(half) * _sinc(half)


def arc_delta(v: float, w: float, dt: float) -> tuple[float, float, float]:
    """Body-frame displacement (dx, dy, dθ) of a constant-velocity arc over ``dt``."""
    phi = w * dt
    return v * dt * _sinc(phi), v * dt * _cosc(phi), phi


def stage_delta(v: float, w: float, dt: float) -> tuple[float, float, float]:
    """Body-frame displacement of Stage's Move(): along the old heading, then rotate."""
    return v * dt, 0.0, w * dt


def body_delta(integrator: str, v: float, w: float, dt: float) -> tuple[float, float, float]:
    """Displacement for ``integrator`` ('exact' or 'stage')."""
    if integrator == "exact":
        return arc_delta(v, w, dt)
    if integrator == "stage":
        return stage_delta(v, w, dt)
    raise ValueError(f"unknown integrator '{integrator}'")


def apply_delta(pose: np.ndarray, delta: tuple[float, float, float]) -> np.ndarray:
    """pose ⊕ delta (translation in the pose's frame, then rotation), yaw wrapped."""
    return compose(pose, delta)


def rotate_then_translate(pose: np.ndarray, delta: tuple[float, float, float]) -> np.ndarray:
    """Stage's odometry update: yaw += dθ first, then (dx, dy) rotated by the NEW yaw."""
    dx, dy, dth = delta
    turned = np.array([pose[0], pose[1], pose[2] + dth])
    return compose(turned, (dx, dy, 0.0))
