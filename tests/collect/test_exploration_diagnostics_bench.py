"""bench_exploration_diagnostics: the snapshot MSE split and the distance after a coverage."""
import numpy as np
import pytest

from slam_predict.collect.stopping import snapshot_mse
from slam_predict.formats.mapserver import UNKNOWN


def test_mse_parts_split_the_stop_rules_mse_by_pixel_class(load_bench):
    diag = load_bench("bench_exploration_diagnostics")
    rng = np.random.default_rng(3)
    a = rng.choice(np.array([0, UNKNOWN, 254], np.uint8), size=(40, 30))
    b = rng.choice(np.array([0, UNKNOWN, 254], np.uint8), size=(40, 30))
    parts = diag.mse_parts(a, b)
    assert parts["total"] == pytest.approx(snapshot_mse(a, b))
    assert parts["new"] + parts["lost"] + parts["changed"] == pytest.approx(parts["total"])
    new = sum(float(int(a[i, j]) - int(b[i, j])) ** 2 for i in range(40) for j in range(30)
              if a[i, j] == UNKNOWN and b[i, j] != UNKNOWN) / a.size
    assert parts["new"] == pytest.approx(new)


def test_distance_after_counts_the_goals_after_coverage_first_reached(load_bench):
    diag = load_bench("bench_exploration_diagnostics")
    goals = [{"coverage": c, "distance_m": d} for c, d in
             [(0.5, 10.0), (0.96, 20.0), (0.94, 5.0), (0.99, 7.0)]]
    assert diag.distance_after(goals, 0.95) == 12.0      # the goals after the first ≥ 0.95
    assert diag.distance_after(goals, 0.995) == 0.0
