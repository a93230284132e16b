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


def _walk():
    # a closed-ish walk: 4 m east, 3 m north, 2 m west (poses every metre)
    xs = [0, 1, 2, 3, 4, 4, 4, 4, 3, 2]
    ys = [0, 0, 0, 0, 0, 1, 2, 3, 3, 3]
    return np.column_stack([xs, ys, np.zeros(len(xs))]).astype(float)


def test_shape_of_the_ground_truth_itself(load_bench):
    bench = load_bench("bench_floor_replay")
    walk = _walk()
    pairs = np.array([[0, 4], [2, 9], [5, 8]])
    assert np.allclose(bench.trajectory_shape(walk, walk, pairs), (1.0, 0.0, 0.0), atol=1e-12)


def test_shape_sees_a_shrunk_and_turned_trajectory(load_bench):
    bench = load_bench("bench_floor_replay")
    walk = _walk()
    # the estimate: the walk shrunk by 1 % about the start, then turned 0.01 rad about it
    c, s = np.cos(0.01), np.sin(0.01)
    shrunk = 0.99 * walk[:, :2]
    estimate = np.column_stack([c * shrunk[:, 0] - s * shrunk[:, 1],
                                s * shrunk[:, 0] + c * shrunk[:, 1], walk[:, 2]])
    pairs = np.array([[0, 4], [2, 9], [5, 8], [1, 7]])
    ratio, angle, residual = bench.trajectory_shape(estimate, walk, pairs)
    assert abs(ratio - 0.99) < 1e-12          # every distance is 0.99 of the true one
    assert abs(angle - 0.01) < 1e-12          # a similarity: least squares finds the turn exactly
    # a rigid fit cannot undo the 1 % shrink: 1 % of the rms distance to the centroid is left
    centred = walk[:, :2] - walk[:, :2].mean(axis=0)
    assert abs(residual - 0.01 * np.sqrt(np.mean(np.sum(centred ** 2, axis=1)))) < 1e-12


def test_turned_frame_keeps_relative_motion(load_bench):
    bench = load_bench("bench_floor_replay")
    walk = _walk()
    moved = bench.in_turned_frame(walk, 0.3, 0.025)
    assert np.allclose(moved[0], [0.025, 0.025, 0.3])
    # distances between poses and heading changes are those of the walk
    assert np.allclose(np.linalg.norm(np.diff(moved[:, :2], axis=0), axis=1),
                       np.linalg.norm(np.diff(walk[:, :2], axis=0), axis=1))
    assert np.allclose(np.diff(moved[:, 2]), np.diff(walk[:, 2]))
