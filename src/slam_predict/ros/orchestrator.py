"""One run of the ROS path: the stop rule, the 10 Hz trajectories and the run record.

:class:`RunMonitor` is the orchestrator node's logic as a plain class, fed by calls (so it is
tested without a master): ``tick(t)`` for every /clock message (or timer tick on a real robot),
``set_map(grid)`` for every /map, ``resolve(lookup)`` to turn the queued sample times into poses
once tf and the ground-truth source have them, ``set_explorer_end`` when the explorer gives up.

It applies the same rules as the in-process episode (:mod:`slam_predict.collect.episode`), from
the same module (:mod:`slam_predict.collect.stopping`: :class:`SnapshotMSE`,
:class:`StuckDetector`, :func:`stop_reason`):

* a sample is queued at every multiple of ``sample_period_s`` (0.1 s; the first at t0 + 0.1 s
  as the in-process loop's first step; ticks may be missed or irregular) and holds ground
  truth, the SLAM pose (tf map→base_link, i.e. map→odom ∘ odom→base_link) and the odometry
  pose (tf odom→base_link) at that time; samples whose poses never arrive within
  ``max_sample_delay_s`` of ROS time are dropped (and counted);
* the SLAM map (the latest /map) is snapshotted over the full xmin..xmax extent every
  ``interval`` s (:class:`~slam_predict.collect.stopping.SnapshotMSE`); the run stops on MSE
  convergence or after ``max_snapshots``, at ``max_sim_time_s`` or after ``max_wall_time_s``
  of wall time; a robot whose ground-truth position stays within ``STUCK_RADIUS_M`` (1 m) of
  one point for ``stuck_timeout_s`` while the explorer still runs is recorded as stuck
  (run.json ``stuck``), not stopped;
* stalls are counted as in Stage: a stall starts at a sample where odometry advanced while the
  ground truth did not move at all (the simulator refused the move).

Times: ``t`` is the ROS time of a tick (sim time, starting at 0, under /clock); the stop rule
uses the elapsed time ``t − t0`` (``t0`` = 0 in simulation, the first tick on a real robot).
"""
from __future__ import annotations

import logging
import math
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from slam_predict.collect import record as rec
from slam_predict.collect.stopping import (
    TIME_EPS,
    SnapshotMSE,
    StopConfig,
    StuckDetector,
    grid_to_snapshot,
    stop_reason,
)
from slam_predict.config import NON_NEGATIVE, POSITIVE, Range

LOG = logging.getLogger(__name__)
STILL_EPS = 1e-9                # m / rad: "did not move at all" (a refused move)


@dataclass
class Sample:
    """Poses at one sample time (s): ground truth (world), SLAM (map), odometry (odom)."""

    t: float
    ground_truth: np.ndarray
    slam: np.ndarray
    odom: np.ndarray


class Unavailable(Exception):
    """A pose at a sample time will never be available (a gap in its source)."""


# lookup(t, now) -> Sample (ready), None (not yet), or raises Unavailable (see RunMonitor.resolve)
PoseLookup = Callable[[float, float], Sample | None]


@dataclass
class MonitorSettings:
    """Sampling of the run (s of ROS time)."""

    sample_period_s: float = 0.1
    max_sample_delay_s: float = 10.0
    RANGES: ClassVar[dict[str, Range]] = {
        "sample_period_s": POSITIVE, "max_sample_delay_s": NON_NEGATIVE}


@dataclass
class RunMonitor:
    """Stop rule, stuck/limit checks and trajectory sampling of one run (module docstring).

    Args:
        stop: the stop-rule settings; interval_s: snapshot interval for this building (s).
        extent: (xmin, ymin, xmax, ymax) m of the snapshot canvas (the SLAM back-end's map extent).
        settings: sampling; t0: elapsed-time origin (s); wall_clock: monotonic seconds.
        on_snapshot: called with (index from 1, image) for each snapshot taken.
    """

    stop: StopConfig
    interval_s: float
    extent: tuple = (-100.0, -100.0, 100.0, 100.0)
    settings: MonitorSettings = field(default_factory=MonitorSettings)
    t0: float = 0.0
    wall_clock: Callable[[], float] = time.monotonic
    on_snapshot: Callable[[int, np.ndarray], None] | None = None

    def __post_init__(self) -> None:
        self.rule = SnapshotMSE(self.stop, self.interval_s)
        self.samples: list[Sample] = []
        self.pending: deque[float] = deque()
        self.grid = None
        self.reason: str | None = None
        self.explorer_end: dict | None = None
        self.now: float | None = None
        self.t_stop: float | None = None
        self.dropped = 0
        self.stalls = 0
        self._stalled = False
        self._next_k = 1
        self.stuck = StuckDetector()    # fed elapsed times (t − t0)
        self.wall_start = self.wall_clock()

    # -- inputs ----------------------------------------------------------------------------
    def tick(self, t: float) -> str | None:
        """ROS time advanced to ``t`` (s): queue a sample, snapshot, check the stop rules.

        Returns the stop reason once the run has ended (later ticks only advance ``now``).
        """
        if self.now is not None and t < self.now - TIME_EPS:
            LOG.warning("time went backwards (%.3f s -> %.3f s): tick ignored", self.now, t)
            return self.reason
        self.now = t
        if self.reason is not None:
            return self.reason
        period = self.settings.sample_period_s
        while self.t0 + self._next_k * period <= t + TIME_EPS:  # every grid time up to t,
            self.pending.append(self.t0 + self._next_k * period)  # even if ticks were missed
            self._next_k += 1
        elapsed = t - self.t0
        if self.rule.due(elapsed) and self.grid is not None:
            self._snapshot(elapsed)
        reason = stop_reason(self.stop, self.rule, elapsed, self.wall_clock() - self.wall_start)
        if reason:
            self.reason, self.t_stop = reason, t
            LOG.info("run stops at %.1f s: %s", elapsed, reason)
        return self.reason

    def set_map(self, grid) -> None:
        """The latest SLAM map (:class:`slam_predict.slam.OccupancyGrid`)."""
        self.grid = grid

    def set_explorer_end(self, t: float, reason: str) -> None:
        """The explorer stopped (no frontier left...): the robot idles, the MSE rule decides."""
        if self.explorer_end is None:
            self.explorer_end = {"t": float(t - self.t0), "reason": str(reason)}

    def request_stop(self, reason: str = "stop_requested") -> None:
        """End the run now (e.g. the operator ends a laboratory run), at the latest tick."""
        if self.reason is None:
            self.reason = reason
            self.t_stop = self.now if self.now is not None else self.t0

    def resolve(self, lookup: PoseLookup) -> int:
        """Turn queued sample times into samples, in order; returns how many were added.

        ``lookup(t, now)`` returns the :class:`Sample` at ``t``, None while some pose is not
        available yet, or raises :class:`Unavailable`; a sample that is unavailable, or still
        missing ``max_sample_delay_s`` after its time, is dropped.
        """
        added = 0
        now = self.now if self.now is not None else -math.inf
        while self.pending:
            t = self.pending[0]
            try:
                sample = lookup(t, now)
            except Unavailable as exc:
                self.pending.popleft()
                self.dropped += 1
                LOG.warning("sample at %.2f s dropped: %s", t, exc)
                continue
            if sample is None:
                if now - t < self.settings.max_sample_delay_s:
                    break
                self.pending.popleft()
                self.dropped += 1
                LOG.warning("sample at %.2f s dropped: poses unavailable for %.1f s", t, now - t)
                continue
            self.pending.popleft()
            self._add(sample)
            added += 1
        return added

    def drop_pending(self) -> int:
        """Give up on every queued sample (end of run); returns how many were dropped."""
        count = len(self.pending)
        self.dropped += count
        self.pending.clear()
        return count

    # -- state -----------------------------------------------------------------------------
    @property
    def done(self) -> bool:
        """The stop rule has ended the run."""
        return self.reason is not None

    @property
    def sim_duration_s(self) -> float:
        """Elapsed ROS time of the run (s): up to the stop, or to the latest tick."""
        end = self.t_stop if self.t_stop is not None else (self.now or self.t0)
        return float(end - self.t0)

    def trajectories(self) -> rec.Trajectories:
        """The samples as :class:`~slam_predict.collect.record.Trajectories`."""
        def stack(name: str) -> np.ndarray:
            return np.array([getattr(s, name) for s in self.samples], float).reshape(-1, 3)
        return rec.Trajectories(np.array([s.t for s in self.samples], float),
                                stack("ground_truth"), stack("slam"), stack("odom"))

    # -- internals -------------------------------------------------------------------------
    def _snapshot(self, elapsed: float) -> None:
        from slam_predict.collect.episode import full_extent_grid
        image = grid_to_snapshot(full_extent_grid(self.grid, self.extent))
        self.rule.add(elapsed, image)
        while self.rule.next_time <= elapsed + TIME_EPS:  # late first map: no burst of snapshots
            self.rule.next_time += self.interval_s
        if self.on_snapshot is not None:
            self.on_snapshot(len(self.rule.times), image)
        mse = self.rule.mses[-1] if self.rule.mses else None
        LOG.info("snapshot %d at %.1f s (MSE %s)", len(self.rule.times), elapsed,
                 "-" if mse is None else f"{mse:.2f}")

    def _add(self, sample: Sample) -> None:
        gt = np.asarray(sample.ground_truth, float)
        odom = np.asarray(sample.odom, float)
        if self.samples:
            prev = self.samples[-1]
            stalled = (_moved(prev.odom, odom) > STILL_EPS
                       and _moved(prev.ground_truth, gt) <= STILL_EPS)
            if stalled and not self._stalled:
                self.stalls += 1
            self._stalled = stalled
        self.stuck.add(float(sample.t) - self.t0, gt[0], gt[1], self.explorer_end is None)
        self.samples.append(Sample(float(sample.t), gt, np.asarray(sample.slam, float), odom))


def _moved(a: np.ndarray, b: np.ndarray) -> float:
    """Largest of the translation (m) and the |rotation| (rad) between two poses."""
    dth = (b[2] - a[2] + math.pi) % (2 * math.pi) - math.pi
    return max(math.hypot(b[0] - a[0], b[1] - a[1]), abs(dth))
