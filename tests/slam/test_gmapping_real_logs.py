"""GMapping on real robot logs (shared/data/slam_inputs): a short slice in CI, full logs slow."""
import json
import math

import numpy as np
import pytest

from slam_predict.slam.gmapping.params import load_params
from slam_predict.slam.gmapping.runner import evaluate, map_check, read_input, run


def run_log(shared_dir, log, seed=1, max_scans=None):
    data = read_input(shared_dir / "data" / "slam_inputs" / f"{log}.log.gz", max_scans)
    params = load_params(shared_dir / "baselines" / f"gmapping_real_{log}.yaml")
    return data, run(data, params, seed)


def test_intel_slice_beats_odometry_and_maps_agree(shared_dir):
    data, result = run_log(shared_dir, "intel", max_scans=150)
    assert result.stats["scans_processed"] == 136 == len(result.poses)
    errors = evaluate(result)
    assert errors["slam"]["trans_mean_m"] < 0.25
    assert errors["slam"]["trans_mean_m"] < 0.05 * errors["odometry"]["trans_mean_m"]
    ours_near_ref, ref_near_ours = map_check(result, data)
    assert ours_near_ref >= 0.8 and ref_near_ours >= 0.8
    occupied = (result.grid.data == 100).sum()
    assert occupied > 1000 and (result.grid.data == 0).sum() > 20 * occupied


def test_same_seed_same_run_other_seed_differs(shared_dir):
    _, a = run_log(shared_dir, "aces", seed=3, max_scans=40)
    _, b = run_log(shared_dir, "aces", seed=3, max_scans=40)
    _, c = run_log(shared_dir, "aces", seed=4, max_scans=40)
    assert np.array_equal(a.poses, b.poses) and np.array_equal(a.grid.data, b.grid.data)
    assert not np.array_equal(a.poses, c.poses)


def expected_processed(data, linear=1.0, angular=0.5):
    """Indices of the scans slam_gmapping processes: the first, then whenever the odometry
    travelled ≥ linear m or turned ≥ angular rad since the last processed one (laser frame)."""
    out, lin, ang = [], 0.0, 0.0
    prev = None
    for k, (x, y, th) in enumerate(data.odometry):
        off = data.laser.pose_in_base[0]
        p = (x + off * math.cos(th), y + off * math.sin(th), th)
        if prev is not None:
            lin += math.hypot(p[0] - prev[0], p[1] - prev[1])
            ang += abs(math.atan2(math.sin(p[2] - prev[2]), math.cos(p[2] - prev[2])))
        prev = p
        if not out or lin >= linear or ang >= angular:
            out.append(k)
            lin = ang = 0.0
    return out


def test_processed_scans_follow_the_update_rule(shared_dir):
    data, result = run_log(shared_dir, "freiburg-101", max_scans=80)
    assert list(result.indices) == expected_processed(data)
    assert np.array_equal(result.times, data.times[result.indices])


@pytest.mark.slow
@pytest.mark.parametrize("log", ["intel", "aces", "csail", "freiburg-101"])
def test_full_log_against_the_real_gmapping(shared_dir, log):
    baseline = json.loads((shared_dir / "baselines" / "gmapping_real.json").read_text())[log]
    data, result = run_log(shared_dir, log)
    assert result.stats["scans_processed"] == baseline["scans_processed"]
    errors = evaluate(result)
    # one seed: allow the real GMapping's seed spread on top of the 1.25 target
    assert errors["slam"]["trans_mean_m"] <= 1.25 * max(baseline["trans_mean_m"])
    assert errors["slam"]["trans_mean_m"] <= 0.25 * errors["odometry"]["trans_mean_m"]
    # aces' map carries a ~0.6 % anisotropic drift over 45 m (the real GMapping's errors there
    # are larger still) that no rigid fit removes: there walls agree to 8 cells, not 2
    tol = 8.0 if log == "aces" else 2.0
    ours_near_ref, ref_near_ours = map_check(result, data, tol=tol)
    assert ours_near_ref >= 0.8 and ref_near_ours >= 0.8
