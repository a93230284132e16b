"""slam_gmapping's compute time in sim time: which scans a real-time GMapping gets to process.

Under ROS, slam_gmapping handles its laser callback on one thread. Processing a scan (scan
matching and registration for every particle) takes time, and after a processed scan whose
stamp is more than ``map_update_interval`` past the last rebuild, ``updateMap`` rebuilds the
published map from scratch: every node of the best particle's trajectory is registered again
(active area, then every beam traced up to maxUrange) and every cell of the map thresholded, so
a rebuild costs more the longer the run. Meanwhile Stage keeps publishing scans in real time;
the subscriber keeps the newest ``queue_size`` (5) and drops older ones. On a slow machine in a
large building GMapping thus sees fewer scans, farther apart, than the lockstep loop gives it.

:class:`ComputeDelay` replays that in sim time with a cost model (CPU seconds on a reference
machine, scaled by ``cpu_factor``) instead of the wall clock, so a run stays deterministic:
scans are queued as they are taken; whenever GMapping is idle it takes the oldest queued scan
and is busy for that scan's cost. The queue is looked at when a scan arrives (:meth:`offer`):
first GMapping takes the queued scans it became free for before the arrival, then the new scan
is queued and taken if GMapping is idle. This hands GMapping the same scans, with the same start
times, as watching the queue continuously would (map → odom is updated up to one scan period
late), and a replay of the sensor log only needs the scan stamps to do the same.

Cost of a processed scan: ``scan_s``, or with ``scan_beams`` > 0 ``scan_s`` × beams /
``scan_beams`` (scan matching is linear in the beams: a 721-beam 360° laser costs 721/541 of the
541-beam laser ``scan_s`` was measured with); of a rebuild:
``rebuild_s_per_map_cell`` × map cells + ``rebuild_s_per_line_cell`` × the beam cells of every
node (Σ over processed scans and beams r ≤ maxRange of min(r, maxUrange)/delta). A scan that is
not processed (below linearUpdate/angularUpdate/temporalUpdate) costs nothing.
"""
from __future__ import annotations

from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from slam_predict.config import NON_NEGATIVE, POSITIVE, Range, check_ranges
from slam_predict.errors import InputError

__all__ = ["COMPUTE_MODELS", "ComputeDelay", "ComputeDelayConfig", "for_backend"]

COMPUTE_MODELS = ("none", "cost")


@dataclass
class ComputeDelayConfig:
    """``slam_compute:`` of collect.yaml. Costs are CPU seconds on the reference machine of
    docs/fidelity.md; ``cpu_factor`` is how many times slower the emulated machine is."""

    model: str = "none"
    queue_size: int = 5
    cpu_factor: float = 1.0
    scan_s: float = 0.0
    rebuild_s_per_map_cell: float = 0.0
    rebuild_s_per_line_cell: float = 0.0
    scan_beams: int = 0             # beams scan_s was measured with; 0: scan_s for every laser
    HASH_OMIT_IF: ClassVar[dict[str, Any]] = {"scan_beams": 0}
    RANGES: ClassVar[dict[str, Range]] = {
        "cpu_factor": POSITIVE, "scan_s": NON_NEGATIVE,
        "rebuild_s_per_map_cell": NON_NEGATIVE, "rebuild_s_per_line_cell": NON_NEGATIVE}

    def __post_init__(self) -> None:
        if self.model not in COMPUTE_MODELS:
            raise ValueError(f"model must be one of {', '.join(COMPUTE_MODELS)}, "
                             f"got '{self.model}'")
        check_ranges("slam_compute", self, positive=("queue_size", "cpu_factor"),
                     non_negative=("scan_s", "rebuild_s_per_map_cell", "rebuild_s_per_line_cell",
                                   "scan_beams"))

    @property
    def enabled(self) -> bool:
        return self.model != "none"


def line_cells(ranges: np.ndarray, max_range: float, max_urange: float, delta: float) -> float:
    """Cells a map rebuild traces for one scan: Σ min(r, maxUrange)/delta over the beams
    0 < r ≤ maxRange (registerScan skips the others)."""
    r = np.asarray(ranges, dtype=float)
    used = r[(r > 0.0) & (r <= max_range)]
    return float(np.minimum(used, max_urange).sum() / delta)


class ComputeDelay:
    """The scan queue and busy time of a real-time slam_gmapping (sim time, s).

    Args:
        config: the cost model.
        map_update_interval: s between rebuilds (slam_gmapping's parameter).
        map_cells: cells of the rebuilt map ((xmax − xmin)(ymax − ymin)/delta²).
        beam_limits: (maxRange, maxUrange, delta) of the GMapping parameters, m.
    """

    def __init__(self, config: ComputeDelayConfig, map_update_interval: float,
                 map_cells: float, beam_limits: tuple[float, float, float]):
        self.config = config
        self.map_update_interval = float(map_update_interval)
        self.map_cells = float(map_cells)
        self.beam_limits = beam_limits
        self.queue: deque[tuple[float, Any]] = deque(maxlen=config.queue_size)
        self.busy_until = -np.inf
        self.last_rebuild = -np.inf
        self.total_line_cells = 0.0
        self.stats = {"scans_queued": 0, "scans_dropped": 0, "scans_handled": 0,
                      "rebuilds": 0, "busy_s": 0.0, "max_rebuild_s": 0.0}

    def offer(self, stamp: float, item: Any,
              handle: Callable[[float, Any], tuple[bool, np.ndarray]]) -> bool:
        """A scan ``item`` taken at ``stamp`` s arrives. ``handle(stamp, item)`` gives a scan to
        GMapping and returns (processed, float ranges). Returns whether the map was rebuilt."""
        rebuilt = False
        for arrived in (False, True):
            if arrived:
                self.push(stamp, item)
            while (due := self.next_due(stamp)) is not None:
                processed, ranges = handle(*due)
                rebuilt = self.handled(due[0], processed, ranges) or rebuilt
        return rebuilt

    def push(self, stamp: float, item: Any) -> None:
        """A scan taken at ``stamp`` s arrives (the oldest queued one is dropped when full)."""
        if len(self.queue) == self.queue.maxlen:
            self.stats["scans_dropped"] += 1
        self.queue.append((float(stamp), item))
        self.stats["scans_queued"] += 1

    def next_due(self, now: float) -> tuple[float, Any] | None:
        """The oldest queued scan if GMapping is idle at ``now`` s, else None."""
        if not self.queue or self.busy_until > now + 1e-9:
            return None
        self.stats["scans_handled"] += 1
        return self.queue.popleft()

    def handled(self, stamp: float, processed: bool, ranges: np.ndarray | None) -> bool:
        """Charge the cost of the scan of ``stamp`` s just handed to GMapping; returns whether
        slam_gmapping would rebuild (and publish) its map after it."""
        if not processed:
            return False
        cfg = self.config
        self.total_line_cells += line_cells(ranges, *self.beam_limits)
        cost = scan_cost(cfg, len(ranges))
        rebuild = stamp - self.last_rebuild > self.map_update_interval
        if rebuild:
            rebuild_s = (cfg.rebuild_s_per_map_cell * self.map_cells
                         + cfg.rebuild_s_per_line_cell * self.total_line_cells)
            cost += rebuild_s
            self.last_rebuild = stamp
            self.stats["rebuilds"] += 1
            self.stats["max_rebuild_s"] = max(self.stats["max_rebuild_s"],
                                              rebuild_s * cfg.cpu_factor)
        cost *= cfg.cpu_factor
        self.busy_until = max(self.busy_until, stamp) + cost
        self.stats["busy_s"] += cost
        return rebuild


def scan_cost(config: ComputeDelayConfig, beams: int) -> float:
    """CPU s (reference machine) of one processed scan of ``beams`` beams."""
    if config.scan_beams <= 0:
        return config.scan_s
    return config.scan_s * beams / config.scan_beams


def for_backend(config: ComputeDelayConfig | None, backend,
                map_update_interval: float) -> ComputeDelay | None:
    """The compute delay of a GMapping back-end (its parameters give the beam limits and the
    map size), or None when ``config`` is None or off (lockstep)."""
    if config is None or not config.enabled:
        return None
    params = getattr(backend, "params", None)
    if params is None or not hasattr(params, "maxUrange"):
        raise InputError("slam_compute applies to the gmapping back-end only (Karto in real "
                         "time: its scan_gate: async)")
    cells = (params.xmax - params.xmin) * (params.ymax - params.ymin) / params.delta ** 2
    return ComputeDelay(config, map_update_interval, cells,
                        (params.maxRange, params.maxUrange, params.delta))
