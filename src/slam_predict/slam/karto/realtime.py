"""slam_toolbox's async node in sim time: which scans a real-time Karto gets to process.

The async node (``async_slam_toolbox_node``) calls ``Mapper::Process`` from its laser callback,
on ROS' one spinner thread, for every scan (no ``shouldProcessScan`` gate); the scan subscriber
keeps the newest 5 scans (message_filters queue 5), so scans that arrive while the mapper is
busy wait there and the oldest are dropped. A separate thread rebuilds the published map every
``map_update_interval`` s (``OccupancyGrid::CreateFromScans`` of every processed scan) while
holding the mapper's mutex: Process waits for it.

:class:`AsyncMapper` replays that in sim time with a cost model (:class:`AsyncCost`, CPU s of
the real library measured by bench/bench_karto_compute.py, × ``cpu_factor``) instead of the
wall clock, so a run stays deterministic. It reuses the queue of
:class:`~slam_predict.slam.compute_delay.ComputeDelay`; the mapper's work is an event list in
sim time: a queued scan starts when the mapper is free (oldest first), a rebuild starts at its
timer tick or, when the mapper is busy then, as soon as it is free.

Costs: a Process call that adds the scan ``process_s`` + ``process_s_per_beam`` × beams, plus,
when it closes a loop, ``closure_s_per_beam`` × beams + ``closure_s_per_node`` × scans in the
graph; a call that does not add it (HasMovedEnough false) ``rejected_s``; a rebuild
``map_s_per_cell`` × cells of the scans' bounding box + ``map_s_per_beam`` × beams of every
scan in the map.
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, ClassVar

from slam_predict.config import AT_LEAST_ONE, NON_NEGATIVE, POSITIVE, Range
from slam_predict.slam.compute_delay import ComputeDelay, ComputeDelayConfig

__all__ = ["AsyncCost", "AsyncMapper", "CallCost"]


@dataclass
class AsyncCost:
    """``async_cost:`` of config/karto.yaml: the async node's scan queue and the real library's
    CPU s per Process call and per map rebuild (defaults: bench/bench_karto_compute.py on 5
    logs x 2 gates, 2026-12-05, 2-core Debian 12 container); ``cpu_factor``: how many times
    slower the emulated machine is."""

    queue_size: int = 5
    cpu_factor: float = 1.0
    process_s: float = 0.0
    process_s_per_beam: float = 4.003e-05
    closure_s_per_beam: float = 1.611e-04
    closure_s_per_node: float = 3.795e-05
    rejected_s: float = 2.085e-06
    map_s_per_cell: float = 1.075e-08
    map_s_per_beam: float = 2.138e-07
    RANGES: ClassVar[dict[str, Range]] = {
        "queue_size": AT_LEAST_ONE, "cpu_factor": POSITIVE, "process_s": NON_NEGATIVE,
        "process_s_per_beam": NON_NEGATIVE, "closure_s_per_beam": NON_NEGATIVE,
        "closure_s_per_node": NON_NEGATIVE, "rejected_s": NON_NEGATIVE,
        "map_s_per_cell": NON_NEGATIVE, "map_s_per_beam": NON_NEGATIVE}

    def call_s(self, call: CallCost) -> float:
        """CPU s (reference machine) of one Process call."""
        if not call.added:
            return self.rejected_s
        cost = self.process_s + self.process_s_per_beam * call.beams
        if call.closed_loop:
            cost += self.closure_s_per_beam * call.beams + self.closure_s_per_node * call.nodes
        return cost

    def rebuild_s(self, cells: float, beams_in_map: float) -> float:
        """CPU s (reference machine) of one map rebuild."""
        return self.map_s_per_cell * cells + self.map_s_per_beam * beams_in_map


@dataclass
class CallCost:
    """What one Process call did: scan added, loop closed, beams, scans in the graph before."""

    added: bool
    closed_loop: bool = False
    beams: int = 0
    nodes: int = 0


class AsyncMapper(ComputeDelay):
    """The scan queue, the mapper's busy time and the map thread's rebuilds (sim time, s).

    Args:
        cost: the cost model and queue size.
        map_update_interval: s between two ticks of the map thread.
        map_size: () -> (grid cells, beams of every scan in the map) of a rebuild now.
    """

    def __init__(self, cost: AsyncCost, map_update_interval: float,
                 map_size: Callable[[], tuple[float, float]]):
        config = ComputeDelayConfig(model="cost", queue_size=cost.queue_size,
                                    cpu_factor=cost.cpu_factor)
        super().__init__(config, map_update_interval, 0.0, (0.0, 0.0, 1.0))
        self.cost = cost
        self.map_size = map_size
        self.next_tick = 0.0
        self.stats["loop_closing_calls"] = 0

    def offer(self, stamp: float, item: Any, handle: Callable[[float, Any], CallCost]) -> bool:
        """A scan ``item`` taken at ``stamp`` s arrives; ``handle(stamp, item)`` runs Process on
        a queued scan and says what it did. Returns whether any scan was handed to Process."""
        handled = self._advance(stamp - 2e-9, handle)   # a tie: the scan arrives first
        self.push(stamp, item)
        return self._advance(stamp, handle) or handled

    def _advance(self, now: float, handle) -> bool:
        """Run the mapper's events (scans and rebuilds) that start by ``now`` s, in time order."""
        handled = False
        while True:
            scan_start = max(self.busy_until, self.queue[0][0]) if self.queue else math.inf
            tick_start = max(self.busy_until, self.next_tick)
            if min(scan_start, tick_start) > now + 1e-9:
                return handled
            if not self.queue or self.next_tick <= self.queue[0][0] + 1e-9:   # asked first
                self._rebuild(tick_start)
                continue
            stamp, item = self.queue.popleft()
            self.stats["scans_handled"] += 1
            call = handle(stamp, item)
            self._charge(scan_start, self.cost.call_s(call))
            self.stats["loop_closing_calls"] += int(call.closed_loop)
            handled = True

    def _rebuild(self, start: float) -> None:
        """The map thread's tick: a rebuild under the mapper's mutex; the next tick one interval
        after this one (ros::Rate), or when the rebuild ends if that is later."""
        cells, beams = self.map_size()
        if beams > 0:   # no scan yet: getOccupancyGrid returns nothing
            busy = self._charge(start, self.cost.rebuild_s(cells, beams))
            self.stats["rebuilds"] += 1
            self.stats["max_rebuild_s"] = max(self.stats["max_rebuild_s"], busy)
        self.next_tick = max(self.next_tick + self.map_update_interval, self.busy_until)

    def _charge(self, start: float, cpu_s: float) -> float:
        """The mapper is busy from ``start`` for ``cpu_s`` × cpu_factor s; returns that."""
        busy = cpu_s * self.cost.cpu_factor
        self.busy_until = start + busy
        self.stats["busy_s"] += busy
        return busy
