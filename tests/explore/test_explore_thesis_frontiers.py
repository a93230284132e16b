"""The thesis explorer's frontier bookkeeping: storing, clearing, clustering, selection."""
from __future__ import annotations

import numpy as np

from slam_predict.explore.thesis_frontiers import Cluster, FrontierStore


def slow_add(stored, cells, reach):
    """findFrontiers' storing loop, written out."""
    stored = list(stored)
    for x, y in cells:
        if all(abs(x - px) > reach or abs(y - py) > reach for px, py in stored):
            stored.append((x, y))
    return stored


def test_add_cells_keeps_points_apart_like_the_slow_loop():
    rng = np.random.default_rng(0)
    store = FrontierStore()
    first = rng.uniform(0, 3, size=(200, 2))
    store.add_cells(first)
    second = rng.uniform(-1, 4, size=(300, 2))
    store.add_cells(second)
    want = slow_add(slow_add([], first, 0.2), second, 0.2)
    np.testing.assert_allclose(store.array()[1], np.array(want))
    assert list(store.points) == list(range(len(want)))   # ids in storing order


def test_clear_goals_removes_the_first_match_and_skips_the_first_entries():
    store = FrontierStore()
    store.add_cells(np.array([[0.0, 0.0], [1.0, 0.0], [1.15, 0.3], [2.0, 0.0], [3.0, 0.0]]))
    store.visited = [(0.05, 0.0), (1.1, 0.1)]          # [0] = home: not used for clearing
    store.unreachable = [(2.0, 0.0), (3.1, -0.1)]      # [0] is skipped by the package too
    store.clear_goals()
    np.testing.assert_allclose(store.array()[1], [[0.0, 0.0], [1.15, 0.3], [2.0, 0.0]])
    assert not store.is_valid((0.0, 0.0)) and not store.is_valid((2.1, 0.1))
    assert not store.is_valid((1.15, 0.3))      # 0.2 box of visited (1.1, 0.1), kept in store
    assert store.is_valid((1.5, 0.3))


def test_clusters_join_within_one_metre_and_merge_within_point_eight():
    store = FrontierStore()
    store.add_cells(np.array([[0.0, 0.0], [0.5, 0.0], [0.9, 0.5],     # one cluster (joins)
                              [5.0, 0.0],                             # alone
                              [2.6, 0.0], [3.0, 0.0]]))               # 1.7 m from the first
    store.update_clusters()
    members = sorted(sorted(c.members) for c in store.clusters)
    assert members == [[0, 1, 2], [3], [4, 5]]
    # a new point bridging the two big clusters joins the first; then they merge (0.8 m)
    store.add_cells(np.array([[1.85, 0.0]]))
    store.update_clusters()
    members = sorted(sorted(c.members) for c in store.clusters)
    assert members == [[0, 1, 2, 4, 5, 6], [3]]
    # a singleton never merges, even when close
    store.add_cells(np.array([[5.5, 0.9]]))
    store.update_clusters()
    assert sorted(sorted(c.members) for c in store.clusters) == [[0, 1, 2, 4, 5, 6], [3, 7]]
    # members that left the store leave their cluster; empty clusters go
    for fid in (3, 7):
        del store.points[fid]
    store.update_clusters()
    assert [sorted(c.members) for c in store.clusters] == [[0, 1, 2, 4, 5, 6]]


def store_with_clusters(groups):
    store = FrontierStore()
    for k, group in enumerate(groups):
        ids = []
        for point in group:
            store.points[store._next_id] = tuple(point)
            ids.append(store._next_id)
            store._next_id += 1
        store.clusters.append(Cluster(k, ids))
    return store


def test_clusters_sort_by_integer_metres_with_seeded_random_ties():
    groups = [[(2.7, 0.0), (3.5, 0.0)], [(0.0, 2.3), (0.0, 2.9)], [(1.9, 0.0), (1.95, 0.1)]]
    orders = set()
    for seed in range(20):
        store = store_with_clusters(groups)
        store.sort_clusters((0.0, 0.0), np.random.default_rng(seed))
        ids = [c.id for c in store.clusters]
        assert ids[0] == 2                              # 1.9 m: int 1, before the 2 m tie
        orders.add(tuple(ids))
    assert orders == {(2, 0, 1), (2, 1, 0)}             # 2.7 m and 2.3 m tie (int 2)
    again = [store_with_clusters(groups) for _ in range(2)]
    for s in again:
        s.sort_clusters((0.0, 0.0), np.random.default_rng(5))
    assert [c.id for c in again[0].clusters] == [c.id for c in again[1].clusters]
    store = store_with_clusters([[(3.0, 0.0), (1.0, 0.0), (2.0, 0.0)]])
    store.sort_clusters((0.0, 0.0), np.random.default_rng(0))
    assert [store.points[m][0] for m in store.clusters[0].members] == [1.0, 2.0, 3.0]


def test_cluster_goal_keeps_the_previous_cluster_then_resumes_at_the_second():
    store = store_with_clusters([[(1.0, 0.0), (1.1, 0.3)], [(3.0, 0.0), (3.2, 0.0)],
                                 [(6.0, 0.0), (6.2, 0.0)]])
    point, cid = store.cluster_goal(previous=None)
    assert cid == 0 and tuple(point) == (1.0, 0.0)
    point, cid = store.cluster_goal(previous=2)         # the previous cluster still exists
    assert cid == 2 and tuple(point) == (6.0, 0.0)
    store.visited = [(9.0, 9.0), (1.0, 0.0)]            # first member of cluster 0 visited
    point, cid = store.cluster_goal(previous=None)
    assert cid == 0 and tuple(point) == (1.1, 0.3)
    store.unreachable = [(6.05, 0.0), (6.25, 0.05)]     # cluster 2 has no valid member
    point, cid = store.cluster_goal(previous=2)         # the package goes on at index 1
    assert cid == 1 and tuple(point) == (3.0, 0.0)


def test_random_goal_is_uniform_over_points_and_none_when_invalid():
    store = FrontierStore()
    store.add_cells(np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]))
    rng = np.random.default_rng(0)
    draws = [tuple(store.random_goal(rng)) for _ in range(300)]
    counts = [draws.count((x, 0.0)) for x in (0.0, 1.0, 2.0)]
    assert min(counts) > 70
    store.unreachable = [(1.0, 0.1)]
    results = [store.random_goal(rng) for _ in range(100)]
    assert any(r is None for r in results)
    assert all(r is None or tuple(r) != (1.0, 0.0) for r in results)


def test_auction_and_nearest_goals():
    store = store_with_clusters([[(4.0, 0.0)], [(0.0, 1.5), (0.0, 1.7)]])
    point, cid = store.auction_goal((0.0, 0.0))          # int(d^2): 16 vs 2
    assert cid == 1 and tuple(point) == (0.0, 1.5)
    store.unreachable = [(0.0, 1.5), (0.0, 1.7)]
    point, cid = store.auction_goal((0.0, 0.0))          # then the clusters after it
    assert cid == 0
    assert tuple(store.nearest_goal((0.0, 0.0))) == (4.0, 0.0)
