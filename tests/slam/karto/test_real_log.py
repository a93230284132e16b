"""Karto on the first scans of the Intel log: error bound against the log's reference, and,
when the real library's outputs are there (bench/bench_karto_diff.py --out, in
$SLAM_PREDICT_KARTO_REF or ../karto_ref beside the project), the same accepted scans."""
import json
import os
from pathlib import Path

import numpy as np
import pytest

from slam_predict import slam
from slam_predict.slam.runner import evaluate, read_input, run

KARTO_REF = Path(os.environ.get("SLAM_PREDICT_KARTO_REF",
                               Path(__file__).resolve().parents[3].parent / "karto_ref"))
REAL = KARTO_REF / "intel" / "real.json"


@pytest.mark.slow
def test_intel_first_scans(shared_data):
    data = read_input(shared_data / "slam_inputs" / "intel.log.gz", 300)
    result = run(data, "karto", slam.params_from_dict("karto", {}), 1)
    errors = evaluate(result)
    assert errors["slam"]["trans_mean_m"] < 0.3
    assert errors["slam"]["trans_mean_m"] < errors["odometry"]["trans_mean_m"]
    if REAL.is_file():
        accepted = [a[0] for a in json.loads(REAL.read_text())["accepted"] if a[0] < 300]
        assert np.array_equal(result.indices, accepted)


ACES_REAL = KARTO_REF / "aces" / "real.json"


@pytest.mark.skipif(not ACES_REAL.is_file(), reason=f"no real-library output in {KARTO_REF}")
def test_aces_equals_the_real_library(shared_data):
    """ACES with the sync gate has no loop closure: every accepted scan and pose must be the
    real karto_sdk's to rounding."""
    data = read_input(shared_data / "slam_inputs" / "aces.log.gz", 120)
    result = run(data, "karto", slam.params_from_dict("karto", {}), 1)
    real = np.array([a for a in json.loads(ACES_REAL.read_text())["accepted"] if a[0] < 120])
    assert np.array_equal(result.indices, real[:, 0].astype(int))
    assert np.allclose(result.poses, real[:, 2:], atol=1e-9)
