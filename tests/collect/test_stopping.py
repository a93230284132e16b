"""The snapshot MSE stop rule against a direct full-image computation; the stuck detector and
the order of the limits that end a run."""
import numpy as np

from slam_predict.collect.stopping import (
    STUCK_DISTANCE_M,
    SnapshotMSE,
    StopConfig,
    StuckDetector,
    grid_to_snapshot,
    snapshot_mse,
    stop_reason,
)
from slam_predict.formats.mapserver import FREE, OCCUPIED, UNKNOWN


def test_grid_to_snapshot_map_saver_values():
    grid = np.array([[-1, 0, 100], [25, 26, 65]], dtype=np.int8)
    assert grid_to_snapshot(grid).tolist() == [[FREE, UNKNOWN, OCCUPIED], [UNKNOWN, FREE, OCCUPIED]]


def test_mse_equals_full_image_reference():
    rng = np.random.default_rng(1)
    for _ in range(20):
        a = np.full((200, 300), UNKNOWN, np.uint8)
        b = a.copy()
        r, c = rng.integers(0, 150), rng.integers(0, 250)
        a[r:r + 40, c:c + 30] = rng.choice([FREE, OCCUPIED], (40, 30))
        b[r + 5:r + 45, c:c + 50] = rng.choice([FREE, OCCUPIED, UNKNOWN], (40, 50))
        ref = np.mean((a.astype(float) - b.astype(float)) ** 2)
        assert np.isclose(snapshot_mse(a, b), ref)
    assert snapshot_mse(a, a) == 0.0


def test_rule_stops_when_map_stops_changing():
    cfg = StopConfig(interval_s=600.0, mse_threshold=10.0)
    rule = SnapshotMSE(cfg, cfg.interval_for(1000.0))
    snap = np.full((100, 100), UNKNOWN, np.uint8)
    assert not rule.due(599.0) and rule.due(600.0)
    snap[:50] = FREE
    assert not rule.add(600.0, snap.copy())     # first snapshot: nothing to compare
    snap[50:] = FREE
    assert not rule.add(1200.0, snap.copy())    # half the map changed: MSE large
    assert rule.add(1800.0, snap.copy())        # unchanged: MSE 0 < 10
    assert rule.reason == "map_converged" and rule.mses[-1] == 0.0
    assert rule.times == [600.0, 1200.0, 1800.0]


def test_small_buildings_use_short_interval_and_cap():
    cfg = StopConfig(max_snapshots=3)
    assert cfg.interval_for(100.0) == 120.0 and cfg.interval_for(300.0) == 600.0
    rule = SnapshotMSE(cfg, 120.0)
    rng = np.random.default_rng(0)
    stops = [rule.add(120.0 * (i + 1), rng.choice([FREE, OCCUPIED], (50, 50)).astype(np.uint8))
             for i in range(3)]
    assert stops == [False, False, True] and rule.reason == "max_snapshots"


def test_stuck_detector_counts_from_the_last_move_of_more_than_stuck_distance():
    stuck = StuckDetector()
    assert stuck.still_for(7.0) == 7.0                 # nothing seen yet: since t0
    stuck.add(1.0, 0.0, 0.0)
    stuck.add(2.0, STUCK_DISTANCE_M * 0.99, 0.0)       # less than the distance: no progress
    assert stuck.still_for(5.0) == 4.0
    stuck.add(3.0, 0.0, STUCK_DISTANCE_M * 1.01)       # measured from the anchor, not the last
    assert stuck.still_for(5.0) == 2.0
    stuck.add(4.0, 0.0, 0.0)                            # back more than the distance
    assert stuck.still_for(5.0) == 1.0


def test_stop_reason_order_and_limits():
    cfg = StopConfig(stuck_timeout_s=30.0, max_sim_time_s=100.0, max_wall_time_s=50.0)
    rule = SnapshotMSE(cfg, 60.0)
    assert stop_reason(cfg, rule, 99.9, 0.0) is None
    assert stop_reason(cfg, rule, 100.0 - 1e-7, 0.0) == "max_sim_time"
    assert stop_reason(cfg, rule, 10.0, 50.0) == "wall_time_limit"
    rule.reason = "map_converged"                       # the MSE rule comes first
    assert stop_reason(cfg, rule, 200.0, 90.0) == "map_converged"


def test_a_stuck_robot_is_recorded_not_stopped():
    """The longest still time counts only while exploring; it flags the run at the timeout."""
    cfg = StopConfig(stuck_timeout_s=30.0, max_sim_time_s=1e9)
    idle = StuckDetector()
    for t in range(0, 41):                              # standing still 0..40 s
        idle.add(float(t), 0.0, 0.0, exploring=t <= 25)  # the explorer stopped at 25 s
    assert idle.record(cfg) == {"longest_still_s": 25.0, "stuck": False}
    stuck = StuckDetector()
    stuck.add(0.0, 0.0, 0.0)
    stuck.add(10.0, 1.0, 0.0)                           # moved: still from 10 s on
    for t in range(11, 42):
        stuck.add(float(t), 1.0, 0.0)
    assert stuck.record(cfg) == {"longest_still_s": 31.0, "stuck": True}
    assert stop_reason(cfg, SnapshotMSE(cfg, 60.0), 41.0, 0.0) is None   # the run goes on
