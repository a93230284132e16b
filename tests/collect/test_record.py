"""run.json's one builder (used by the in-process episode and the ROS path) against values
computed directly from a synthetic run."""
import math

import numpy as np
import pytest

from slam_predict.collect import record as rec
from slam_predict.collect.settings import load_settings
from slam_predict.collect.stopping import SnapshotMSE, StopConfig


def square_run(n=400):
    """A robot driving a 2 m square (10 Hz) with SLAM drifting slowly off the ground truth."""
    t = 0.1 * np.arange(1, n + 1)
    side = (np.arange(n) // 100) % 4
    step = np.stack([np.cos(side * np.pi / 2), np.sin(side * np.pi / 2)], axis=1) * 0.02
    xy = np.cumsum(step, axis=0)
    gt = np.column_stack([xy, side * np.pi / 2])
    rng = np.random.default_rng(5)
    slam = gt + np.cumsum(rng.normal(0.0, 1e-3, gt.shape), axis=0)
    return rec.Trajectories(t, gt, slam, gt.copy())


def test_build_record_fields(run_record_keys):
    settings = load_settings()
    traj = square_run()
    rule = SnapshotMSE(StopConfig(), 60.0)
    rule.times, rule.mses, rule.reason = [60.0, 120.0], [3.5], "map_converged"
    info = rec.RunInfo("square", "", 2, 7, odometry_error={"model": "x"})
    stuck = {"longest_still_s": 12.5, "stuck": False}
    end = rec.RunEnd("map_converged", {"t": 30.0, "reason": "no_frontiers"}, 40.0, 1.5, 3, 0.9,
                     stuck, 0.97)
    record = rec.build_record(info, settings, {"sim": "abc"}, end, traj, rule, 12.0, {"sim": 2})
    assert set(record) == run_record_keys and record["stuck"] == stuck
    assert record["coverage_swept"] == 0.97
    assert record["distance_m"] == pytest.approx(0.02 * 399)
    assert record["rotation_rad"] == pytest.approx(3 * math.pi / 2)
    assert record["snapshots"] == [{"t": 60.0, "mse": None}, {"t": 120.0, "mse": 3.5}]
    assert record["odometry_model"] == settings.sim.odom.model     # none given: the settings'
    assert (record["stop_reason"], record["sim_duration_s"], record["stalls"]) == (
        "map_converged", 40.0, 3)
    assert record["config_hashes"] == {"sim": "abc"} and record["timing"] == {"sim": 2.0}
    assert record["metric"]["poses"] == len(traj.t) and record["metric"]["trans_mean"] > 0
    assert record["metric"]["info"]["seed"] == [7, 1]


def test_build_record_of_a_run_without_snapshots():
    """A run that ended before its first snapshot (a limit) has an empty list."""
    rule = SnapshotMSE(StopConfig(), 60.0)
    end = rec.RunEnd("max_sim_time", None, 30.0, 1.0, 0, None)
    record = rec.build_record(rec.RunInfo("square"), load_settings(), {}, end, square_run(), rule,
                              None, {})
    assert record["snapshots"] == [] and record["stop_reason"] == "max_sim_time"
    assert "stuck" not in record                          # not watched: no entry


def test_a_run_whose_robot_never_moved_has_no_metric():
    """One distinct ground-truth pose (the pauses removed): no relation can be sampled, so the
    record holds ``metric: null`` and says why, instead of failing the run."""
    t = 0.1 * np.arange(1, 101)
    still = np.zeros((100, 3))
    traj = rec.Trajectories(t, still, still + 0.01, still.copy())
    end = rec.RunEnd("map_converged", None, 10.0, 1.0, 0, 0.001)
    record = rec.build_record(rec.RunInfo("still"), load_settings(), {}, end, traj,
                              SnapshotMSE(StopConfig(), 60.0), 50.0, {})
    assert record["metric"] is None and record["metric_note"] == rec.NO_METRIC_NOTE
    assert record["coverage"] == 0.001 and record["distance_m"] == 0.0
    moved = rec.build_record(rec.RunInfo("square"), load_settings(), {}, end, square_run(),
                             SnapshotMSE(StopConfig(), 60.0), 50.0, {})
    assert rec.with_metric([record, moved, {"metric": None}]) == [moved]
