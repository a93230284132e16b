"""Trajectory tree: paths, shared pasts, compaction of dead branches."""
import numpy as np

from slam_predict.slam.gmapping.tree import TrajectoryTree


def test_paths_share_their_past_and_survive_compaction():
    tree = TrajectoryTree((0, 0, 0), capacity=4)
    leaves = np.zeros(3, dtype=np.int64)
    rng = np.random.default_rng(0)
    history = {}
    for scan in range(60):
        parents = leaves[rng.integers(0, 3, 3)] if scan % 3 == 2 else leaves  # "resampling"
        leaves = tree.add_nodes(rng.normal(size=(3, 3)), parents, scan)
        tree.add_reading(scan, np.full(4, float(scan)), t=10.0 + scan)
        for i, node in enumerate(leaves):
            history[(scan, i)] = tree.pose[node].copy()
    assert tree.size < 60 * 3  # dead branches were dropped
    for i, node in enumerate(leaves):
        scans, poses = tree.trajectory(int(node))
        assert list(scans) == list(range(60))
        assert np.array_equal(poses[-1], history[(59, i)])
        for k in scans:
            assert np.array_equal(tree.readings[int(k)], np.full(4, float(k)))
            assert tree.times[int(k)] == 10.0 + k
    assert tree.path(int(leaves[0]))[0] == 0  # the root


def test_compact_remaps_and_drops_unreachable_readings():
    tree = TrajectoryTree((1, 2, 3))
    a = tree.add_nodes(np.zeros((2, 3)), [0, 0], 0)
    tree.add_reading(0, np.ones(2), 0.0)
    b = tree.add_nodes(np.ones((2, 3)), a, 1)
    tree.add_reading(1, np.ones(2), 1.0)
    remap = tree.compact(b[:1])
    assert tree.size == 3 and remap[b[1]] == -1 and remap[a[1]] == -1
    assert list(tree.trajectory(int(remap[b[0]]))[0]) == [0, 1]
    assert np.array_equal(tree.pose[0], [1, 2, 3])
