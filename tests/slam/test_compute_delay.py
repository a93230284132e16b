"""The compute-delay model of a real-time slam_gmapping: queue and busy-time rules against a
hand-worked event schedule, and the closed loop with zero cost equal to lockstep."""
from __future__ import annotations

import dataclasses
import heapq
import math

import numpy as np
import pytest

from slam_predict.explore import run as runner
from slam_predict.explore.loop import ClosedLoop
from slam_predict.slam.compute_delay import ComputeDelay, ComputeDelayConfig, line_cells
from slam_predict.slam.gmapping.params import GMappingParams
from slam_predict.world.load import load_plan


def reference_schedule(stamps, processed, scan_cost, queue_size):
    """Discrete-event simulation in continuous time: scan arrivals and "GMapping is free"
    events in time order (free first on a tie); a free GMapping takes the oldest queued scan;
    the queue keeps the newest queue_size. Returns the stamps handed to GMapping, in order."""
    events = [(t, 1) for t in stamps]
    heapq.heapify(events)
    handed, queue, busy = [], [], False
    while events:
        now, kind = heapq.heappop(events)
        if now > stamps[-1]:
            break                                  # the model is looked at until the last scan
        if kind == 1:
            queue = (queue + [now])[-queue_size:]
        else:
            busy = False
        while queue and not busy:
            stamp = queue.pop(0)
            handed.append(stamp)
            if processed(stamp):
                busy = True
                heapq.heappush(events, (round(max(now, stamp) + scan_cost, 6), 0))  # as stamps
    return handed


def run_model(stamps, processed, config):
    delay = ComputeDelay(config, map_update_interval=1e9, map_cells=0.0,
                         beam_limits=(10.0, 5.0, 0.05))
    handed = []

    def handle(stamp, _):
        handed.append(stamp)
        return processed(stamp), np.array([1.0])

    for now in stamps:
        delay.offer(now, None, handle)
    return handed, delay


@pytest.mark.parametrize("scan_cost, queue_size", [(0.35, 5), (1.25, 5), (0.55, 2), (0.15, 1)])
def test_scans_handed_follow_the_reference_schedule(scan_cost, queue_size):
    stamps = [round(0.1 * k, 1) for k in range(1, 200)]
    rng = np.random.default_rng(3)
    flags = dict(zip(stamps, rng.random(len(stamps)) < 0.4, strict=True))
    config = ComputeDelayConfig(model="cost", queue_size=queue_size, scan_s=scan_cost)
    handed, delay = run_model(stamps, flags.__getitem__, config)
    assert handed == reference_schedule(stamps, flags.__getitem__, scan_cost, queue_size)
    assert delay.stats["scans_dropped"] == len(stamps) - len(handed) - len(delay.queue)
    assert delay.stats["scans_dropped"] > 0


def test_a_slow_rebuild_leaves_only_the_newest_scans():
    """A rebuild of 2 s at t = 0.1 s: the scans of 0.2-1.6 s are dropped, 1.7-2.1 s queued."""
    config = ComputeDelayConfig(model="cost", queue_size=5, rebuild_s_per_map_cell=1.0)
    delay = ComputeDelay(config, map_update_interval=5.0, map_cells=2.0,
                         beam_limits=(10.0, 5.0, 0.05))
    delay.push(0.1, "first")
    stamp, _ = delay.next_due(0.1)
    assert delay.handled(stamp, True, np.array([1.0]))        # first processed scan rebuilds
    assert delay.busy_until == pytest.approx(2.1)
    for k in range(2, 21):
        delay.push(k / 10, k)
        assert delay.next_due(k / 10) is None                 # still rebuilding
    delay.push(2.1, 21)
    assert [item for _, item in delay.queue] == [17, 18, 19, 20, 21]
    assert delay.next_due(2.1) == (1.7, 17)
    assert delay.stats["scans_dropped"] == 15


def test_rebuilds_follow_slam_gmappings_stamp_rule():
    config = ComputeDelayConfig(model="cost")
    delay = ComputeDelay(config, 5.0, 0.0, (10.0, 5.0, 0.05))
    stamps = (1.0, 5.0, 6.0, 6.01, 11.0, 11.02)
    rebuilt = [delay.handled(t, True, np.array([1.0])) for t in stamps]
    assert rebuilt == [True, False, False, True, False, True]   # strictly more than 5 s later
    assert not delay.handled(20.0, False, np.array([1.0]))  # unprocessed scans never rebuild


def test_rebuild_cost_grows_with_the_traced_beam_cells():
    config = ComputeDelayConfig(model="cost", cpu_factor=2.0, scan_s=0.1,
                                rebuild_s_per_map_cell=1e-3, rebuild_s_per_line_cell=1e-4)
    delay = ComputeDelay(config, 5.0, 1000.0, (10.0, 5.0, 0.05))
    ranges = np.array([0.0, 1.0, 7.0, 10.0, 12.0])    # 0 and > maxRange skipped; 7, 10 → 5
    assert line_cells(ranges, 10.0, 5.0, 0.05) == pytest.approx((1 + 5 + 5) / 0.05)
    delay.handled(0.0, True, ranges)
    delay.handled(6.0, True, ranges)
    expected = 2.0 * (0.1 + 1.0 + 1e-4 * 2 * 220)
    assert delay.busy_until == pytest.approx(6.0 + expected)
    assert delay.stats["max_rebuild_s"] == pytest.approx(2.0 * (1.0 + 1e-4 * 440))


def test_config_is_validated():
    with pytest.raises(ValueError, match="model"):
        ComputeDelayConfig(model="wallclock")
    with pytest.raises(ValueError, match="queue_size"):
        ComputeDelayConfig(queue_size=0)
    with pytest.raises(ValueError, match="cpu_factor"):
        ComputeDelayConfig(cpu_factor=0.0)


def _gmapping_loop(root, compute, seconds=20.0):
    settings = runner.load_explore_settings(root / "config")
    settings.explore = dataclasses.replace(settings.explore, strategy="nearest")
    world = load_plan(root / "worlds" / "tiny.world")
    params = dataclasses.replace(GMappingParams(), particles=3)
    loop = ClosedLoop(world, 5, settings.nav, settings.explore, settings.sim,
                      map_source="gmapping", slam_params=params, compute=compute)
    loop.run(seconds)
    return loop


def test_zero_cost_equals_lockstep(root):
    lockstep = _gmapping_loop(root, None)
    free = _gmapping_loop(root, ComputeDelayConfig(model="cost"))
    np.testing.assert_array_equal(np.array(free.log.true_poses), np.array(lockstep.log.true_poses))
    assert free.source.filter.count == lockstep.source.filter.count
    assert free.delay.stats["scans_dropped"] == 0


def test_a_slow_machine_processes_fewer_scans(root):
    lockstep = _gmapping_loop(root, None)
    slow = _gmapping_loop(root, ComputeDelayConfig(model="cost", scan_s=1.0))
    assert slow.delay.stats["scans_dropped"] > 0
    assert slow.source.filter.reading_count < lockstep.source.filter.reading_count
    assert slow.source.filter.count <= 20.0 / 1.0 + 1     # at most one per second of sim time


def test_scan_cost_scales_with_beams_only_when_asked():
    from slam_predict.config import config_hash
    from slam_predict.slam.compute_delay import scan_cost

    fixed = ComputeDelayConfig(model="cost", scan_s=0.448)
    per_beam = ComputeDelayConfig(model="cost", scan_s=0.448, scan_beams=541)
    assert scan_cost(fixed, 721) == 0.448
    assert scan_cost(per_beam, 541) == 0.448
    assert math.isclose(scan_cost(per_beam, 721), 0.448 * 721 / 541)
    assert config_hash(fixed) == config_hash(ComputeDelayConfig(model="cost", scan_s=0.448,
                                                                scan_beams=0))
    assert config_hash(per_beam) != config_hash(fixed)


def test_a_wider_laser_keeps_gmapping_busy_longer():
    config = ComputeDelayConfig(model="cost", scan_s=0.2, scan_beams=100)
    delays = []
    for beams in (100, 300):
        delay = ComputeDelay(config, 5.0, 0.0, (30.0, 30.0, 0.05))
        delay.offer(0.0, "scan", lambda stamp, item, n=beams: (True, np.full(n, 1.0)))
        delays.append(delay.busy_until)
    assert math.isclose(delays[0], 0.2) and math.isclose(delays[1], 0.6)
