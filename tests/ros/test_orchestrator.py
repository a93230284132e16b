"""RunMonitor (the orchestrator's logic) fed by calls: sampling, stop rule, stuck, limits, stall."""
from __future__ import annotations

import numpy as np
import pytest

from slam_predict.collect.episode import full_extent_grid
from slam_predict.collect.stopping import STUCK_RADIUS_M, SnapshotMSE, StopConfig, grid_to_snapshot
from slam_predict.ros.orchestrator import MonitorSettings, RunMonitor, Sample, Unavailable
from slam_predict.slam import OccupancyGrid


def ticks(monitor, t_end, dt=0.1, start=0.0, lookup=None):
    """Tick from ``start`` to ``t_end`` (inclusive) every ``dt``; resolve with ``lookup``."""
    n = int(round((t_end - start) / dt))
    for k in range(n + 1):
        t = round(start + k * dt, 9)
        monitor.tick(t)
        if lookup is not None:
            monitor.resolve(lookup)
        if monitor.done:
            return t
    return None


def moving(t, now):
    """A robot driving along x at 0.5 m/s; SLAM = truth shifted; odometry = truth."""
    gt = np.array([0.5 * t, 0.0, 0.0])
    return Sample(t, gt, gt + [0.01, 0.0, 0.0], gt)


def make(stop=None, interval=120.0, **kwargs):
    return RunMonitor(stop or StopConfig(), interval, extent=(-5.0, -5.0, 5.0, 5.0), **kwargs)


def grid(value=0, shape=(40, 60), origin=(-1.0, -2.0)):
    data = np.full(shape, -1, np.int8)
    data[5:20, 10:30] = value
    return OccupancyGrid(data, 0.05, origin)


def test_samples_every_period_starting_at_one_period():
    m = make()
    ticks(m, 2.0, dt=0.05, lookup=moving)
    t = m.trajectories().t
    np.testing.assert_allclose(t, np.arange(1, 21) * 0.1, atol=1e-9)
    traj = m.trajectories()
    np.testing.assert_allclose(traj.slam - traj.ground_truth, [[0.01, 0, 0]] * 20)


def test_samples_wait_for_poses_then_resolve_in_order():
    m = make()
    available = {"until": 0.35}

    def late(t, now):
        return moving(t, now) if t <= available["until"] + 1e-9 else None

    ticks(m, 1.0, lookup=late)
    assert len(m.samples) == 3 and len(m.pending) == 7
    available["until"] = 10.0
    m.resolve(late)
    assert [round(s.t, 3) for s in m.samples] == [round(0.1 * k, 3) for k in range(1, 11)]


def test_missing_samples_are_dropped_after_the_delay_and_unavailable_at_once():
    m = make(settings=MonitorSettings(0.1, max_sample_delay_s=1.0))

    def gap(t, now):
        if 0.25 < t < 0.45:
            raise Unavailable("gap")
        if 0.55 < t < 0.65:
            return None            # never arrives
        return moving(t, now)

    ticks(m, 3.0, lookup=gap)
    got = [round(s.t, 2) for s in m.samples]
    assert 0.3 not in got and 0.4 not in got and 0.6 not in got
    assert m.dropped == 3 and 0.7 in got and 3.0 in got


def test_snapshot_schedule_and_mse_rule_match_snapshotmse():
    stop = StopConfig(mse_threshold=10.0, stuck_timeout_s=1e9)
    images = []
    m = make(stop, interval=120.0, on_snapshot=lambda i, img: images.append((i, img)))
    m.set_map(grid(0))
    ticks(m, 130.0)
    m.set_map(grid(100))   # a changed map: MSE large
    ticks(m, 250.0, start=130.1)
    m.set_map(grid(100))   # unchanged: converges at the third snapshot
    end = ticks(m, 400.0, start=250.1)
    assert m.reason == "map_converged" and end == pytest.approx(360.0)
    assert m.rule.times == pytest.approx([120.0, 240.0, 360.0])
    # the same images through SnapshotMSE directly
    canvas = (-5.0, -5.0, 5.0, 5.0)
    ref = SnapshotMSE(stop, 120.0)
    for t, value in ((120.0, 0), (240.0, 100), (360.0, 100)):
        ref.add(t, grid_to_snapshot(full_extent_grid(grid(value), canvas)))
    assert m.rule.mses == pytest.approx(ref.mses) and ref.reason == "map_converged"
    assert [i for i, _ in images] == [1, 2, 3] and images[0][1].shape == (200, 200)
    assert m.sim_duration_s == pytest.approx(360.0)


def test_no_snapshot_without_a_map_a_late_map_and_max_snapshots():
    stop = StopConfig(max_snapshots=3, max_sim_time_s=1e9, stuck_timeout_s=1e9)
    m = make(stop, interval=10.0)
    ticks(m, 25.0)
    assert m.rule.times == []
    m.set_map(grid(0))
    ticks(m, 29.9, start=25.1)       # the late first map: one snapshot now, the next at 30 s
    assert m.rule.times == pytest.approx([25.1])
    m.set_map(grid(100))
    ticks(m, 39.9, start=30.0)
    m.set_map(grid(0))
    end = ticks(m, 60.0, start=40.0)
    assert m.reason == "max_snapshots" and end == pytest.approx(40.0)
    assert m.rule.times == pytest.approx([25.1, 30.0, 40.0])


def standing(t, now):
    """Robot not moving (ground truth and odometry constant)."""
    return Sample(t, np.zeros(3), np.zeros(3), np.zeros(3))


def test_stuck_is_recorded_only_while_exploring_and_does_not_stop_the_run():
    stop = StopConfig(stuck_timeout_s=30.0, max_sim_time_s=100.0)
    m = make(stop)
    end = ticks(m, 200.0, lookup=standing)
    assert m.reason == "max_sim_time" and end == pytest.approx(100.0)
    assert m.stuck.record(stop)["stuck"]
    m = make(stop)
    ticks(m, 5.0, lookup=standing)
    m.set_explorer_end(5.0, "Exploration stopped.")
    end = ticks(m, 200.0, start=5.1, lookup=standing)
    assert m.reason == "max_sim_time" and end == pytest.approx(100.0)
    assert m.explorer_end == {"t": 5.0, "reason": "Exploration stopped."}
    assert m.stuck.record(stop) == {"longest_still_s": pytest.approx(5.0, abs=0.11),
                                    "stuck": False, "stuck_at_end": False,
                                    "radius_m": STUCK_RADIUS_M}


def test_moving_robot_is_not_stuck_and_wall_limit():
    clock = {"t": 0.0}
    stop = StopConfig(stuck_timeout_s=5.0, max_wall_time_s=50.0, max_sim_time_s=1e9)
    m = make(stop, wall_clock=lambda: clock["t"])
    for k in range(1, 400):
        clock["t"] = k * 0.2
        m.tick(k * 0.1)
        m.resolve(moving)
        if m.done:
            break
    assert m.reason == "wall_time_limit" and m.now == pytest.approx(25.0)


def test_ticks_after_the_stop_only_advance_time_and_backwards_time_is_ignored():
    m = make(StopConfig(max_sim_time_s=1.0))
    ticks(m, 1.0)
    assert m.reason == "max_sim_time" and len(m.pending) == 10
    m.tick(1.5)
    assert len(m.pending) == 10 and m.now == 1.5 and m.sim_duration_s == pytest.approx(1.0)
    m.tick(0.5)
    assert m.now == 1.5


def test_stalls_count_refused_moves():
    m = make()
    odom = np.zeros(3)
    gt = np.zeros(3)
    pattern = [1, 1, 0, 0, 1, 0, 0, 0, 1, 1]   # 1 = moving, 0 = stalled (odometry moves only)
    for k, move in enumerate(pattern, start=1):
        odom = odom + [0.05, 0.0, 0.0]
        if move:
            gt = gt + [0.05, 0.0, 0.0]
        m._add(Sample(0.1 * k, gt.copy(), gt.copy(), odom.copy()))
    assert m.stalls == 2
    # standing still (neither moves) is not a stall
    m2 = make()
    for k in range(5):
        m2._add(Sample(0.1 * k, np.zeros(3), np.zeros(3), np.zeros(3)))
    assert m2.stalls == 0


def test_real_robot_time_origin():
    m = make(StopConfig(max_sim_time_s=2.0), t0=1.7e9)
    end = ticks(m, 1.7e9 + 5.0, start=1.7e9, lookup=moving)
    assert m.reason == "max_sim_time" and end == pytest.approx(1.7e9 + 2.0)
    assert m.sim_duration_s == pytest.approx(2.0)
    assert len(m.samples) == 20


def test_missed_and_irregular_ticks_still_sample_every_grid_time():
    m = make()
    for t in (0.0, 0.1, 0.2, 0.73, 0.8, 1.55, 2.0):
        m.tick(t)
        m.resolve(moving)
    np.testing.assert_allclose(m.trajectories().t, np.arange(1, 21) * 0.1, atol=1e-9)


def test_a_requested_stop_ends_the_run_at_the_latest_tick():
    m = make()
    ticks(m, 3.0, lookup=moving)
    m.request_stop()
    assert m.done and m.reason == "stop_requested" and m.sim_duration_s == pytest.approx(3.0)
    m.request_stop("other")
    assert m.reason == "stop_requested"
