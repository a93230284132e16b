"""bench/bench_floor_replay.py's pure parts: the scaled perfect odometer and the overrides."""

import numpy as np


def _path():
    # drive 1 m along x, turn left 90 degrees on the spot, drive 2 m along y
    return np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.0, np.pi / 2],
                     [1.0, 2.0, np.pi / 2]])


def test_scale_one_is_the_ground_truth(load_bench):
    bench = load_bench("bench_floor_replay")
    path = _path()
    assert np.array_equal(bench.scaled_truth(path, 1.0), path)


def test_scaled_odometer_stretches_translations_only(load_bench):
    bench = load_bench("bench_floor_replay")
    odometry = bench.scaled_truth(_path(), 1.01)
    # by hand: 1.01 m along x, the same turn, then 2.02 m along y
    expected = np.array([[0.0, 0.0, 0.0], [1.01, 0.0, 0.0], [1.01, 0.0, np.pi / 2],
                         [1.01, 2.02, np.pi / 2]])
    assert np.allclose(odometry, expected, atol=1e-12)


def test_overrides_are_typed(load_bench):
    bench = load_bench("bench_floor_replay")
    got = bench.parse_overrides(["particles=1", "delta=0.025", "range_sensor_angles=false",
                                 "random_stream=numpy"])
    assert got == {"particles": 1, "delta": 0.025, "range_sensor_angles": False,
                   "random_stream": "numpy"}
    assert isinstance(got["particles"], int) and isinstance(got["delta"], float)
