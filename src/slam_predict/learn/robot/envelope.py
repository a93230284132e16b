"""Robot-aware predictions that never improve when the robot gets worse.

A user expects the error of a shorter-range laser, a narrower field of view or larger odometry
errors to be no smaller. The boosted models are monotone by construction, the Gaussian process
and the elastic net are not, so a component can fall as the laser gets worse (measured on
own-robots, 2026-12-05: ε_r at 360° rose from 0.0293 to 0.0325 rad as the range grew from 12 to
30 m). The post-check here makes every component monotone in the four robot inputs, for any
query, without refitting:

1. the model is evaluated on a grid of robots for the plan (:func:`robot_axes`: the training
   range of each input, plus a node at its worse plausible limit; the rows are
   :func:`~slam_predict.learn.robot.monotone_check.grid_rows`, as the training-time check's);
2. each grid value is raised to the largest value of any grid robot at least as good
   (:func:`envelope`: a running maximum along each input, from the best robot to the worst);
3. the query is read from that grid by multilinear interpolation (:func:`interpolate`), which
   keeps the monotonicity between nodes.

Where the model is already monotone the grid values are its own and only the interpolation
between nodes differs from it.
"""
from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence

import numpy as np

from slam_predict.learn.robot.monotone_check import WORSE

# Nodes across the training range of each input: the laser range most (the error changes
# fastest with it, roughly as a power of it), geometric.
INNER_NODES = {"laser_range_max_m": 8, "laser_fov_deg": 4, "odom_xy_error": 4,
               "odom_yaw_error": 4}
RANGE_LIMIT_M = 0.1       # the worst laser range on the grid, m
FOV_LIMIT_DEG = 1.0       # the narrowest field of view on the grid, deg
ODOM_OUTER_FACTOR = 10.0  # odometry nodes reach this × the largest trained error
LOG_AXES = ("laser_range_max_m",)


def robot_axes(input_ranges: Mapping[str, Sequence[float]]) -> dict[str, np.ndarray]:
    """Grid nodes per robot input, ordered from the best robot to the worst: the training
    range (:data:`INNER_NODES`, geometric for the laser range) plus one node at the worse
    plausible limit (range 0.1 m, fov 1°, odometry :data:`ODOM_OUTER_FACTOR` × the trained
    maximum). A robot better than the training range reads the range's best edge: the
    models' extrapolation towards better robots is not trusted."""
    axes = {}
    for name, direction in WORSE.items():
        low, high = (float(v) for v in input_ranges[name])
        count = INNER_NODES[name]
        if name == "laser_range_max_m":
            inner = np.geomspace(max(low, RANGE_LIMIT_M), max(high, low), count)
            worst = RANGE_LIMIT_M
        elif name == "laser_fov_deg":
            inner, worst = np.linspace(low, high, count), FOV_LIMIT_DEG
        else:
            inner, worst = np.linspace(low, high, count), ODOM_OUTER_FACTOR * max(high, 1e-6)
        nodes = np.unique(np.append(inner, worst))
        axes[name] = nodes[::-1] if direction < 0 else nodes
    return axes


def envelope(values: np.ndarray) -> np.ndarray:
    """Each grid value raised to the largest value at any node that is at least as good on
    every axis (axes run from best to worst): a running maximum along each axis in turn."""
    out = np.asarray(values, dtype=float)
    for axis in range(out.ndim):
        out = np.maximum.accumulate(out, axis=axis)
    return out


def _position(nodes: np.ndarray, value: float, log: bool) -> tuple[int, float]:
    """(index i, fraction t) of ``value`` between nodes i and i + 1 (clamped to the axis),
    measured on a log scale when ``log``."""
    ascending = nodes[0] <= nodes[-1]
    seq = nodes if ascending else nodes[::-1]
    if log:
        seq, value = np.log(seq), math.log(max(value, 1e-300))
    pos = float(np.interp(value, seq, np.arange(len(seq), dtype=float)))
    if not ascending:
        pos = len(seq) - 1 - pos
    i = min(int(np.floor(pos)), len(nodes) - 2)
    return i, pos - i


def interpolate(grid: np.ndarray, axes: Mapping[str, np.ndarray],
                query: Mapping[str, float]) -> float:
    """Multilinear interpolation of ``grid`` (shaped as ``axes``) at the query robot: of the
    log of the values when all are positive (errors fall roughly as powers of the inputs),
    with the laser range on a log scale. Both keep the interpolation monotone."""
    places = [_position(nodes, float(query[name]), name in LOG_AXES)
              for name, nodes in axes.items()]
    logs = bool(np.all(grid > 0))
    table = np.log(grid) if logs else np.asarray(grid, dtype=float)
    total = 0.0
    for corner in itertools.product((0, 1), repeat=len(places)):
        weight = 1.0
        index = []
        for (i, t), bit in zip(places, corner, strict=True):
            weight *= t if bit else 1.0 - t
            index.append(i + bit)
        if weight:
            total += weight * float(table[tuple(index)])
    return float(np.exp(total)) if logs else total
