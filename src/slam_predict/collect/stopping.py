"""The thesis' stop rule: compare SLAM map snapshots taken at fixed sim-time intervals.

A snapshot is the SLAM occupancy grid rendered as an 8-bit map_saver image over the full
configured map extent (xmin..xmax, ymin..ymax at ``delta``): 0 occupied, 205 unknown, 254 free.
Every ``interval_s`` of sim time (120 s for buildings under ``small_area_m2``) a snapshot is taken;
the run stops when the mean squared error between two consecutive snapshots is below
``mse_threshold``, or after ``max_snapshots`` snapshots.

The limits that also end a run (:func:`stop_reason`, in this order after the MSE rule):
``max_sim_time_s`` of sim time, then ``max_wall_time_s`` of wall time. A robot whose ground-truth
position stays within ``STUCK_RADIUS_M`` of one point for ``stuck_timeout_s`` while the explorer
still runs is recorded as stuck (:class:`StuckDetector`: run.json ``stuck``): standing still, and
also shuttling back and forth without getting anywhere. The run goes on
until the MSE rule ends it, as the seed study's orchestrator, which has no stuck rule, would
(a stuck robot leaves the map unchanged, so the next snapshot ends the run). The in-process
episode and the ROS path's orchestrator both apply these two functions.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from slam_predict.config import AT_LEAST_ONE, NON_NEGATIVE, POSITIVE, Range, check_ranges
from slam_predict.formats.mapserver import UNKNOWN, occupancy_to_image

# m: leaving a circle of this radius around the point where the robot's stuck clock started
# resets the clock. Records without ``radius_m`` used 0.1 m, which a robot shuttling 0.25-0.5 m
# for good (REVERSE_BLOCKED forward, a blind escape back) kept resetting (docs/notes/exploration.md,
# 2026-12-06). Not fitted; any progress of an exploring robot leaves 1 m in far less than
# ``stuck_timeout_s``.
STUCK_RADIUS_M = 1.0
TIME_EPS = 1e-6          # s: sim times are compared with this tolerance


@dataclass
class StopConfig:
    """Stop-rule settings (s, m², grey levels²)."""

    interval_s: float = 600.0
    small_interval_s: float = 120.0
    small_area_m2: float = 250.0
    mse_threshold: float = 10.0
    max_snapshots: int = 18
    stuck_timeout_s: float = 300.0
    max_sim_time_s: float = 4 * 3600.0
    max_wall_time_s: float = 3600.0
    RANGES: ClassVar[dict[str, Range]] = {
        "interval_s": POSITIVE, "small_interval_s": POSITIVE, "small_area_m2": NON_NEGATIVE,
        "mse_threshold": NON_NEGATIVE, "max_snapshots": AT_LEAST_ONE, "stuck_timeout_s": POSITIVE,
        "max_sim_time_s": POSITIVE, "max_wall_time_s": POSITIVE}

    def __post_init__(self) -> None:
        positive = ("interval_s", "small_interval_s", "stuck_timeout_s", "max_sim_time_s",
                    "max_wall_time_s")
        check_ranges("stop", self, positive=positive,
                     non_negative=("small_area_m2", "mse_threshold"))
        if self.max_snapshots < 1:
            raise ValueError(f"stop.max_snapshots must be >= 1, got {self.max_snapshots}")

    def interval_for(self, free_area_m2: float) -> float:
        """Snapshot interval (s) for a building of ``free_area_m2``."""
        return self.small_interval_s if free_area_m2 < self.small_area_m2 else self.interval_s


def grid_to_snapshot(grid: np.ndarray) -> np.ndarray:
    """map_saver image (uint8, row 0 = top) of an int8 OccupancyGrid array (row 0 = bottom)."""
    return occupancy_to_image(grid)


def snapshot_mse(a: np.ndarray, b: np.ndarray) -> float:
    """Mean squared grey-level difference of two equal-size snapshots (over every pixel)."""
    if a.shape != b.shape:
        raise ValueError(f"snapshot shapes differ: {a.shape} vs {b.shape}")
    known = (a != UNKNOWN) | (b != UNKNOWN)
    rows = np.flatnonzero(known.any(axis=1))
    if rows.size == 0:
        return 0.0
    cols = np.flatnonzero(known.any(axis=0))
    window = (slice(rows[0], rows[-1] + 1), slice(cols[0], cols[-1] + 1))
    diff = a[window].astype(np.int32) - b[window].astype(np.int32)
    return float(np.square(diff).sum()) / a.size


@dataclass
class SnapshotMSE:
    """Stateful stop rule: feed it snapshots when ``due``; it says when to stop.

    Only the last snapshot is kept.
    """

    config: StopConfig
    interval_s: float
    next_time: float = field(init=False)
    last: np.ndarray | None = None
    times: list[float] = field(default_factory=list)
    mses: list[float] = field(default_factory=list)
    reason: str | None = None

    def __post_init__(self) -> None:
        self.next_time = self.interval_s

    def due(self, t: float) -> bool:
        """True when a snapshot should be taken at sim time ``t`` (s)."""
        return t + 1e-9 >= self.next_time

    def add(self, t: float, snapshot: np.ndarray) -> bool:
        """Record a snapshot taken at ``t``; returns True when the run should stop."""
        if self.last is not None:
            mse = snapshot_mse(self.last, snapshot)
            self.mses.append(mse)
            if mse < self.config.mse_threshold:
                self.reason = "map_converged"
        self.last = snapshot
        self.times.append(t)
        self.next_time += self.interval_s
        if self.reason is None and len(self.times) >= self.config.max_snapshots:
            self.reason = "max_snapshots"
        return self.reason is not None


class StuckDetector:
    """Sim time since the robot last left the circle of ``STUCK_RADIUS_M`` (ground truth, m)
    around the point where the clock started, the longest such time while the explorer was
    running, and that time at the last position given (0 once the explorer has ended)."""

    def __init__(self, t0: float = 0.0):
        self._anchor: tuple | None = None
        self._anchor_t = float(t0)
        self.longest_s = 0.0
        self.at_end_s = 0.0

    def add(self, t: float, x: float, y: float, exploring: bool = True) -> None:
        """The ground-truth position (m) at sim time ``t`` (s); times must not decrease.
        ``exploring``: the explorer still runs (only then does standing still count)."""
        self.at_end_s = self.still_for(t) if exploring else 0.0
        self.longest_s = max(self.longest_s, self.at_end_s)
        if self._anchor is None or math.hypot(x - self._anchor[0],
                                              y - self._anchor[1]) > STUCK_RADIUS_M:
            self._anchor, self._anchor_t = (float(x), float(y)), float(t)

    def still_for(self, t: float) -> float:
        """Sim time (s) at ``t`` since the robot last left its ``STUCK_RADIUS_M`` circle."""
        return t - self._anchor_t

    def record(self, stop: StopConfig) -> dict:
        """run.json's ``stuck``: the longest time within the circle while exploring (s), whether
        it reached ``stuck_timeout_s`` (``stuck``: at some time; ``stuck_at_end``: still so when
        the run ended, the robot never got out), and the circle's radius (m)."""
        return {"longest_still_s": round(self.longest_s, 3),
                "stuck": bool(self.longest_s + TIME_EPS >= stop.stuck_timeout_s),
                "stuck_at_end": bool(self.at_end_s + TIME_EPS >= stop.stuck_timeout_s),
                "radius_m": STUCK_RADIUS_M}


def stop_reason(stop: StopConfig, rule: SnapshotMSE, elapsed_s: float,
                wall_s: float) -> str | None:
    """Why the run ends at sim time ``elapsed_s`` after ``wall_s`` of wall time, or None:
    ``rule``'s reason first, then ``max_sim_time``, ``wall_time_limit``."""
    if rule.reason:
        return rule.reason
    if elapsed_s + TIME_EPS >= stop.max_sim_time_s:
        return "max_sim_time"
    if wall_s >= stop.max_wall_time_s:
        return "wall_time_limit"
    return None
