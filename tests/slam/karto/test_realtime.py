"""The async node's real-time emulation: its queue and mapper events against a time-stepped
reference, its cost model against the real library's CPU times, and the back-end in
``scan_gate: async``."""
import json
import os
from collections import deque
from pathlib import Path

import numpy as np
import pytest

from slam_predict import slam
from slam_predict.config import config_hash
from slam_predict.slam.karto.params import KartoParams
from slam_predict.slam.karto.realtime import AsyncCost, AsyncMapper, CallCost
from slam_predict.slam.runner import read_input, run

ROOT = Path(__file__).resolve().parents[3]
KARTO_REF = Path(os.environ.get("SLAM_PREDICT_KARTO_REF", ROOT.parent / "karto_ref"))
DT = 0.001   # s, the reference's time step; every time and cost below is a multiple of it


def cost_of(stamp: float) -> CallCost:
    """A deterministic mix of cheap and expensive Process calls (a 10-beam laser)."""
    k = round(stamp * 10)
    return CallCost(added=k % 3 != 2, closed_loop=k % 7 == 0, beams=10, nodes=k)


COST = AsyncCost(queue_size=3, process_s=0.05, process_s_per_beam=0.0, closure_s_per_beam=0.02,
                 closure_s_per_node=0.0, rejected_s=0.0, map_s_per_cell=0.0,
                 map_s_per_beam=0.003)


def reference(stamps, interval: float, end: float):
    """The mapper thread and the map thread stepped every DT: (handled stamps, rebuild starts)."""
    queue, handled, rebuilds = deque(maxlen=COST.queue_size), [], []
    arrivals = {round(s / DT): s for s in stamps}
    busy_until, next_tick, scans = 0, 0, 0
    for step in range(round(end / DT) + 1):
        if step in arrivals:
            queue.append(arrivals[step])
        while step >= busy_until:   # zero-cost events chain within one step
            if step >= next_tick and (not queue or next_tick <= round(queue[0] / DT)):
                if scans:
                    rebuilds.append(step * DT)
                busy_until = step + round(COST.rebuild_s(0.0, scans * 10) / DT)
                next_tick = max(next_tick + round(interval / DT), busy_until)
            elif queue:
                stamp = queue.popleft()
                call = cost_of(stamp)
                handled.append(stamp)
                scans += call.added
                busy_until = step + round(COST.call_s(call) / DT)
            else:
                break
    return handled, rebuilds


def emulated(stamps, interval: float):
    state = {"scans": 0}
    rebuilds = []
    mapper = AsyncMapper(COST, interval, lambda: (0.0, state["scans"] * 10))
    original = mapper._rebuild

    def logged(start):
        if state["scans"]:
            rebuilds.append(start)
        original(start)

    mapper._rebuild = logged
    handled = []

    def handle(stamp, _item):
        handled.append(stamp)
        call = cost_of(stamp)
        state["scans"] += call.added
        return call

    for stamp in stamps:
        mapper.offer(stamp, None, handle)
    return handled, rebuilds, mapper


def test_queue_and_rebuilds_match_a_time_stepped_reference():
    stamps = [round(0.1 * k, 3) for k in range(1, 120)]
    handled, rebuilds, mapper = emulated(stamps, 1.0)
    ref_handled, ref_rebuilds = reference(stamps, 1.0, stamps[-1])
    assert handled == ref_handled
    assert np.allclose(rebuilds, ref_rebuilds)
    assert mapper.stats["scans_dropped"] > 0 and mapper.stats["rebuilds"] == len(rebuilds)
    assert len(handled) < len(stamps)


def test_a_fast_machine_handles_every_scan():
    cost = AsyncCost(cpu_factor=1e-6)
    mapper = AsyncMapper(cost, 5.0, lambda: (1e6, 1e4))
    handled = []
    for k in range(100):
        mapper.offer(0.1 * k, k, lambda s, item: handled.append(item) or CallCost(True, True,
                                                                                  1000, 500))
    assert handled == list(range(100)) and mapper.stats["scans_dropped"] == 0


def test_async_cost_is_hashed_only_when_changed():
    base = KartoParams()
    assert config_hash(base) == config_hash(KartoParams(scan_gate="sync"))
    changed = KartoParams(async_cost=AsyncCost(cpu_factor=2.0))
    assert config_hash(changed) != config_hash(base)


def test_bad_async_cost_is_an_input_error():
    from slam_predict.errors import InputError
    with pytest.raises(InputError, match="cpu_factor"):
        slam.params_from_dict("karto", {"async_cost": {"cpu_factor": -1.0}}, "karto.yaml")


@pytest.mark.skipif(not (KARTO_REF / "intel" / "real.json").is_file(),
                    reason=f"no real-library output in {KARTO_REF}")
def test_default_costs_are_the_bench_fit_and_predict_the_real_cpu(root, load_bench):
    bench = load_bench("bench_karto_compute")
    runs = bench.load(KARTO_REF)
    fitted = bench.fit(runs)
    shipped = slam.load_params("karto", root / "config" / "karto.yaml").async_cost
    for key, value in fitted.items():
        assert getattr(shipped, key) == pytest.approx(value, rel=1e-3, abs=1e-9), key
        assert getattr(AsyncCost(), key) == getattr(shipped, key), key
    for line in bench.check(runs, fitted)[1:]:
        process_ratio, map_ratio = float(line.split()[5]), float(line.split()[8])
        assert 0.75 < process_ratio < 1.3 and 0.7 < map_ratio < 1.4, line


def _aces(shared_data, scans):
    return read_input(shared_data / "slam_inputs" / "aces.log.gz", scans)


def test_async_on_a_fast_machine_is_the_ungated_mapper(shared_data):
    data = _aces(shared_data, 60)
    fast = {"scan_gate": "async", "async_cost": {"cpu_factor": 1e-6}}
    ours = run(data, "karto", slam.params_from_dict("karto", fast), 1)
    none = run(data, "karto", slam.params_from_dict("karto", {"scan_gate": "none"}), 1)
    assert np.array_equal(ours.indices, none.indices)
    assert np.allclose(ours.poses, none.poses)


def test_async_on_a_slow_machine_drops_scans(shared_data):
    data = _aces(shared_data, 60)
    slow = slam.params_from_dict("karto", {"scan_gate": "async",
                                           "async_cost": {"cpu_factor": 1000.0}})
    backend = slam.create("karto", params=slow, laser=data.laser)
    for t, odom, ranges in zip(data.times, data.odometry, data.ranges, strict=True):
        backend.update(odom, ranges, t)
    stats = backend.stats()["async"]
    assert stats["scans_dropped"] > 0
    assert stats["scans_handled"] + stats["scans_dropped"] + len(backend.realtime.queue) == 60
    assert len(backend.stats()["accepted_input_indices"]) < 40
    assert json.dumps(stats)   # stats.json-ready
