"""Grid check that a robot-aware model never predicts a smaller error for a worse robot.

A worse robot has a shorter laser, a narrower field of view or larger odometry errors
(:data:`WORSE`). Trees built with monotonic constraints satisfy this by construction; a
Gaussian process or an elastic net with a coefficient of the wrong sign need not (the shipped
mean ε_r Gaussian process of 2026-12-05 predicted more error with a 30 m laser than with a
12 m one). :func:`monotone_violations` evaluates a component model on a Cartesian grid of the
four robot inputs — the training box and beyond it (laser ranges down to 0.1 m, fields of view
down to 10°, odometry errors up to 3 × the training maximum) — for every given plan row
(the laser's blind fraction follows the range through the plan's sight-line curve) and
reports, per robot input, the largest relative DROP of the value or of an interval bound
when the robot gets worse along that input's axis. A model that learns the laser's angular
resolution is checked at every resolution of its training points: whether finer beams help or
hurt is not known beforehand (more beams match better but cost more compute, which drops
scans), so the resolution has no direction of its own.
"""
from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import numpy as np

from slam_predict.learn.robot.inputs import RESOLUTION_INPUT, ROBOT_INPUTS

# +1: a larger value is a worse robot; -1: a smaller value is
WORSE = {"laser_range_max_m": -1, "laser_fov_deg": -1, "odom_xy_error": 1,
         "odom_yaw_error": 1}
TOLERANCE = 1e-9      # relative drop accepted as rounding
MIN_RANGE_M = 0.1     # shortest laser range of the grid, m
MIN_FOV_DEG = 10.0    # narrowest field of view of the grid, deg
ODOM_FACTOR = 3.0     # odometry grid up to this × the training maximum


def robot_axes(input_ranges: Mapping[str, Sequence[float]], max_urange_m: float | None,
               points: int = 7) -> dict[str, np.ndarray]:
    """Per robot input, grid values ordered from the best robot to the worst: the training
    range (``points`` values) plus the extrapolation beyond it (module doc)."""
    axes = {}
    for name in ROBOT_INPUTS:
        low, high = (float(v) for v in input_ranges[name])
        inside = np.linspace(low, high, points)
        if name == "laser_range_max_m":
            top = max(high, float(max_urange_m or high))
            values = np.concatenate([[MIN_RANGE_M, 1.0, 0.5 * low], inside, [top]])
        elif name == "laser_fov_deg":
            values = np.concatenate([[MIN_FOV_DEG, 0.5 * low], inside, [360.0]])
        else:
            values = np.concatenate([[0.0], inside, [ODOM_FACTOR * high]])
        values = np.unique(values)
        axes[name] = values[::-1] if WORSE[name] < 0 else values
    return axes


def grid_rows(plan_row: np.ndarray, names: Sequence[str], axes: Mapping[str, np.ndarray],
              blind: Callable[[float], float] | None) -> np.ndarray:
    """(n_range, n_fov, n_xy, n_yaw, d) raw input rows: ``plan_row`` (d,) with the robot
    inputs set to every grid combination and ``laser_blind_fraction`` (when an input)
    computed by ``blind(range_m)``."""
    shape = tuple(len(axes[n]) for n in ROBOT_INPUTS)
    rows = np.broadcast_to(np.asarray(plan_row, float), (*shape, len(names))).copy()
    for axis, name in enumerate(ROBOT_INPUTS):
        view = [1] * len(ROBOT_INPUTS)
        view[axis] = shape[axis]
        rows[..., names.index(name)] = axes[name].reshape(view)
    if "laser_blind_fraction" in names:
        if blind is None:
            raise ValueError("the model reads laser_blind_fraction: give the plan's curve")
        fractions = np.array([blind(r) for r in axes["laser_range_max_m"]])
        rows[..., names.index("laser_blind_fraction")] = fractions.reshape(-1, 1, 1, 1)
    return rows


def worst_drops(values: np.ndarray) -> dict[str, float]:
    """Per robot input, the largest relative drop of ``values`` (shape (..., n_range, n_fov,
    n_xy, n_yaw)) from one grid step to the next worse one (0 when it never drops)."""
    out = {}
    offset = values.ndim - len(ROBOT_INPUTS)
    for axis, name in enumerate(ROBOT_INPUTS):
        step = np.diff(values, axis=offset + axis)
        base = np.abs(np.take(values, range(values.shape[offset + axis] - 1),
                              axis=offset + axis))
        drop = -step / np.maximum(base, 1e-300)
        out[name] = float(max(0.0, drop.max())) if drop.size else 0.0
    return out


def monotone_violations(model, names: Sequence[str], plan_rows: np.ndarray,
                        blinds: Sequence[Callable[[float], float] | None],
                        axes: Mapping[str, np.ndarray], confidence: float = 0.9,
                        runs: int = 2) -> dict[str, float]:
    """Per robot input, the largest relative drop (as :func:`worst_drops`) of the value and
    of both interval bounds of ``model`` (a :class:`~slam_predict.learn.robot.plain.
    LogScaleModel`) over the grid ``axes`` at every plan row of ``plan_rows`` (each with its
    blind-fraction function of ``blinds``)."""
    from slam_predict.learn.robot.plain import is_std

    worst = dict.fromkeys(ROBOT_INPUTS, 0.0)
    for plan_row, blind in zip(plan_rows, blinds, strict=True):
        rows = grid_rows(plan_row, list(names), axes, blind)
        flat = rows.reshape(-1, rows.shape[-1])
        bounds = (model.interval(flat, confidence, runs) if is_std(model.component)
                  else model.interval(flat, confidence))
        for series in (model.predict(flat), bounds[:, 0], bounds[:, 1]):
            drops = worst_drops(np.asarray(series).reshape(rows.shape[:-1]))
            worst = {n: max(worst[n], drops[n]) for n in ROBOT_INPUTS}
    return worst


def passes(drops: Mapping[str, float], tolerance: float = TOLERANCE) -> bool:
    """Whether no robot input's largest drop exceeds ``tolerance``."""
    return all(v <= tolerance for v in drops.values())


def check_fitted(fitted: Mapping[str, Mapping[str, object]], tables, curves: Mapping | None,
                 axes: Mapping[str, np.ndarray], confidence: float,
                 runs: int) -> dict[str, dict[str, dict[str, float]]]:
    """{component: {kind: per-robot-input largest drop}} of every fitted model of
    :func:`slam_predict.learn.robot.train.fit_all`, over the grid ``axes`` at one POINT row
    of each training building (``tables``; ``curves``: building → sight-line curve, needed
    when the models read the blind fraction)."""
    from slam_predict.features.sightline import blind_fraction

    worlds = sorted(set(tables.point_world))
    first = [int(np.flatnonzero(tables.point_world == w)[0]) for w in worlds]
    blinds = [None if not curves else (lambda r, c=curves[w]: blind_fraction(c, r))
              for w in worlds]
    plan_rows = tables.point_X[first]
    if RESOLUTION_INPUT in tables.names:   # every trained resolution at every building
        j = tables.names.index(RESOLUTION_INPUT)
        values = np.unique(tables.point_X[:, j])
        plan_rows = np.repeat(plan_rows, len(values), axis=0)
        plan_rows[:, j] = np.tile(values, len(first))
        blinds = [blind for blind in blinds for _ in values]
    return {component: {kind: monotone_violations(model, tables.names, plan_rows, blinds,
                                                  axes, confidence, runs)
                        for kind, model in models.items()}
            for component, models in fitted.items()}
