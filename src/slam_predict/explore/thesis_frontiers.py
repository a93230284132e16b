"""The aau explorer's frontier bookkeeping (``ExplorationPlanner``), for the thesis explorer.

Frontier *points* persist between planning rounds: :meth:`FrontierStore.add_cells` stores a
frontier cell only when no stored point lies within ``max_goal_range`` (0.2 m) on both axes
(``findFrontiers``, cells in index order). Points leave the store when seen
(:func:`~slam_predict.explore.thesis_map.seen_mask`, applied only while more than one point is
stored), or when a visited / unreachable goal lies within ``max_goal_range`` on both axes —
the first such stored point per visited / unreachable entry and round, skipping the first
entry of each list (index 0: ``visited[0]`` is the home point; the package skips
``unreachable[0]`` too). A goal is *valid* (``check_efficiency_of_goal``) when no visited
(home included) or unreachable point lies within ``max_goal_range`` on both axes.

Clusters persist too (``clusterFrontiers``, its strategy 1): members that left the store are
dropped, then each stored point not yet in a cluster joins the first cluster (in the current
cluster order) with a member closer than ``join_dist`` (1 m) on both axes, or starts a new
cluster; clusters of more than one member with members closer than ``merge_dist`` (0.8 m) on
both axes are merged into the earliest of them, transitively. The package can put a point into
two clusters (a neighbour cluster found before its own); here a point has one cluster.

Selection (frontier_selection 5, single robot): members sorted by Euclidean distance to the
robot (``sort(4)``), clusters by the integer distance of their nearest member,
int(sqrt(int(d²))) in m (``sort(5)``; the comparator's ties — and its undefined result for
one-member clusters — are broken randomly here); the goal is the nearest valid member of the
cluster of the previous goal while that cluster has one, else of the first cluster with one
(``determine_goal(4)``; like the package, after the previous cluster fails the search resumes
at the second cluster).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree


@dataclass
class Cluster:
    """A frontier cluster: its id and member frontier ids."""

    id: int
    members: list[int]


def _box_near(points: np.ndarray, x: float, y: float, reach: float) -> np.ndarray:
    """Mask of ``points`` (n, 2) within ``reach`` (m) of (x, y) on both axes (inclusive)."""
    if len(points) == 0:
        return np.zeros(0, bool)
    return (np.abs(points[:, 0] - x) <= reach) & (np.abs(points[:, 1] - y) <= reach)


@dataclass
class FrontierStore:
    """Stored frontier points, visited / unreachable goals and clusters (m)."""

    max_goal_range: float = 0.2
    join_dist: float = 1.0
    merge_dist: float = 0.8
    points: dict[int, tuple[float, float]] = field(default_factory=dict)  # id -> (x, y)
    visited: list[tuple[float, float]] = field(default_factory=list)
    unreachable: list[tuple[float, float]] = field(default_factory=list)
    clusters: list[Cluster] = field(default_factory=list)
    _next_id: int = 0
    _next_cluster: int = 0

    # ------------------------------------------------------------------ stored points
    def array(self) -> tuple[np.ndarray, np.ndarray]:
        """(ids, (n, 2) points) in storage order."""
        ids = np.fromiter(self.points.keys(), int, len(self.points))
        pts = np.array(list(self.points.values()), float).reshape(-1, 2)
        return ids, pts

    def add_cells(self, cells: np.ndarray) -> int:
        """Store the frontier cells (m, in visiting order) that have no stored point within
        ``max_goal_range`` on both axes; returns how many were stored."""
        reach = self.max_goal_range
        buckets: dict[tuple[int, int], list[tuple[float, float]]] = {}

        def key(x: float, y: float) -> tuple[int, int]:
            return int(math.floor(x / reach)), int(math.floor(y / reach))

        for x, y in self.points.values():
            buckets.setdefault(key(x, y), []).append((x, y))
        added = 0
        for x, y in cells:
            kx, ky = key(x, y)
            near = any(abs(px - x) <= reach and abs(py - y) <= reach
                       for dx in (-1, 0, 1) for dy in (-1, 0, 1)
                       for px, py in buckets.get((kx + dx, ky + dy), ()))
            if not near:
                self.points[self._next_id] = (float(x), float(y))
                self._next_id += 1
                buckets.setdefault((kx, ky), []).append((x, y))
                added += 1
        return added

    def remove_seen(self, seen: np.ndarray) -> None:
        """Drop the stored points flagged in ``seen`` (storage order), as clearSeenFrontiers
        does only while more than one point is stored."""
        if len(self.points) <= 1:
            return
        for fid, flag in zip(list(self.points), seen, strict=False):
            if flag:
                del self.points[fid]

    def clear_goals(self) -> None:
        """clearVisitedFrontiers + clearUnreachableFrontiers (see the module docstring)."""
        for goal in self.visited[1:] + self.unreachable[1:]:
            ids, pts = self.array()
            hits = np.nonzero(_box_near(pts, goal[0], goal[1], self.max_goal_range))[0]
            if len(hits):
                del self.points[int(ids[hits[0]])]

    def is_valid(self, point) -> bool:
        """check_efficiency_of_goal: no visited or unreachable point within range."""
        done = np.array(self.visited + self.unreachable, float).reshape(-1, 2)
        return not _box_near(done, float(point[0]), float(point[1]), self.max_goal_range).any()

    # ---------------------------------------------------------------------- clusters
    def update_clusters(self) -> None:
        """clearVisitedAndSeenFrontiersFromClusters + clusterFrontiers."""
        for cluster in self.clusters:
            cluster.members = [m for m in cluster.members if m in self.points]
        self.clusters = [c for c in self.clusters if c.members]
        clustered = {m for c in self.clusters for m in c.members}
        for fid, (x, y) in self.points.items():
            if fid not in clustered:
                self._join(fid, x, y)
        self._merge()

    def _join(self, fid: int, x: float, y: float) -> None:
        for cluster in self.clusters:
            pts = np.array([self.points[m] for m in cluster.members])
            if ((np.abs(pts[:, 0] - x) < self.join_dist)
                    & (np.abs(pts[:, 1] - y) < self.join_dist)).any():
                cluster.members.append(fid)
                return
        self.clusters.append(Cluster(self._next_cluster, [fid]))
        self._next_cluster += 1

    def _merge(self) -> None:
        """Merge clusters of > 1 member that have members closer than merge_dist on both
        axes: each connected group into its earliest cluster."""
        big = [k for k, c in enumerate(self.clusters) if len(c.members) > 1]
        if len(big) < 2:
            return
        owner = np.concatenate([[k] * len(self.clusters[k].members) for k in big])
        pts = np.array([self.points[m] for k in big for m in self.clusters[k].members])
        pairs = cKDTree(pts).query_pairs(self.merge_dist * (1 - 1e-9), p=np.inf,
                                         output_type="ndarray")
        pairs = pairs[owner[pairs[:, 0]] != owner[pairs[:, 1]]]
        if len(pairs) == 0:
            return
        n = len(self.clusters)
        graph = coo_matrix((np.ones(len(pairs)), (owner[pairs[:, 0]], owner[pairs[:, 1]])),
                           shape=(n, n))
        _, label = connected_components(graph, directed=False)
        first: dict[int, Cluster] = {}
        kept: list[Cluster] = []
        for k, cluster in enumerate(self.clusters):
            if label[k] in first:
                first[label[k]].members.extend(cluster.members)
            else:
                first[label[k]] = cluster
                kept.append(cluster)
        self.clusters = kept

    def sort_clusters(self, robot_xy, rng: np.random.Generator) -> None:
        """sort(4) then sort(5): members by distance, clusters by integer distance (m) of
        their nearest member, ties in random order."""
        rx, ry = float(robot_xy[0]), float(robot_xy[1])
        keys = []
        for cluster in self.clusters:
            pts = np.array([self.points[m] for m in cluster.members])
            dist = np.hypot(pts[:, 0] - rx, pts[:, 1] - ry)
            order = np.argsort(dist, kind="stable")
            cluster.members = [cluster.members[i] for i in order]
            keys.append(int(math.sqrt(int(dist[order[0]] ** 2))))
        shuffle = rng.permutation(len(self.clusters))
        ranked = sorted(shuffle, key=lambda k: keys[k])
        self.clusters = [self.clusters[k] for k in ranked]

    def _first_valid(self, cluster: Cluster) -> np.ndarray | None:
        for m in cluster.members:
            if self.is_valid(self.points[m]):
                return np.array(self.points[m], float)
        return None

    def cluster_goal(self, previous: int | None) -> tuple[np.ndarray, int] | None:
        """determine_goal(4): (point, cluster id) from the sorted clusters, or None."""
        n = len(self.clusters)
        start = next((k for k, c in enumerate(self.clusters) if c.id == previous), 0)
        # the package's ring buffer: after the previous cluster it restarts at index 1
        order = list(range(n)) if start == 0 else [start] + [k for k in range(1, n)
                                                             if k != start]
        for k in order:
            point = self._first_valid(self.clusters[k])
            if point is not None:
                return point, self.clusters[k].id
        return None

    def random_goal(self, rng: np.random.Generator) -> np.ndarray | None:
        """determine_goal(3): a uniformly drawn stored point if valid, else None."""
        if not self.points:
            return None
        _, pts = self.array()
        point = pts[int(rng.integers(len(pts)))]
        return point if self.is_valid(point) else None

    def auction_goal(self, robot_xy) -> tuple[np.ndarray, int] | None:
        """The single-robot auction (global costmap iteration): the cluster with the lowest
        bid int(d²) of its first member (ties: the earlier), then the clusters after it."""
        if not self.clusters:
            return None
        rx, ry = float(robot_xy[0]), float(robot_xy[1])
        bids = [int((self.points[c.members[0]][0] - rx) ** 2
                    + (self.points[c.members[0]][1] - ry) ** 2) for c in self.clusters]
        best = int(np.argmin(bids))
        for step in range(len(self.clusters)):
            cluster = self.clusters[(best + step) % len(self.clusters)]
            point = self._first_valid(cluster)
            if point is not None:
                return point, cluster.id
        return None

    def nearest_goal(self, robot_xy) -> np.ndarray | None:
        """sort(2) + determine_goal(2): the nearest valid stored point (ties: storage
        order), or None."""
        if not self.points:
            return None
        _, pts = self.array()
        dist = np.hypot(pts[:, 0] - float(robot_xy[0]), pts[:, 1] - float(robot_xy[1]))
        for k in np.argsort(dist, kind="stable"):
            if self.is_valid(pts[k]):
                return pts[k]
        return None
