"""The particles' trajectory tree (openslam_gmapping TNode) in flat arrays.

Each processed scan adds one node per particle: the particle's pose (laser pose, m/rad), its
parent node and the index of the scan (readings shared by all particles). Node 0 is the root
(initial pose, no reading). Resampled particles hang their new node under the survivor's node,
so trajectories share their common past. Nodes no particle leads to any more are dropped by
:meth:`TrajectoryTree.compact`, which runs by itself when the arrays fill up.
"""
from __future__ import annotations

from collections.abc import Sequence

import numpy as np


class TrajectoryTree:
    """Append-only node arrays with garbage collection of dead branches."""

    def __init__(self, root_pose, capacity: int = 1024):
        capacity = max(int(capacity), 2)
        self.pose = np.zeros((capacity, 3))
        self.parent = np.full(capacity, -1, dtype=np.int64)
        self.scan = np.full(capacity, -1, dtype=np.int64)
        self.pose[0] = np.asarray(root_pose, dtype=float)
        self.size = 1
        self.readings: dict[int, np.ndarray] = {}
        self.times: dict[int, float] = {}
        self._live_after_compact = 1

    def add_reading(self, index: int, ranges: np.ndarray, t: float) -> None:
        """Store the readings (and time, s) of processed scan number ``index``."""
        self.readings[index] = ranges
        self.times[index] = float(t)

    def add_nodes(self, poses: np.ndarray, parents: Sequence[int], scan: int) -> np.ndarray:
        """New nodes (one per row of ``poses``) under ``parents``, all for scan ``scan``.

        Only ancestors of ``parents`` survive a compaction triggered here, so the caller must
        replace every node index it holds by the returned new indices.
        """
        poses = np.asarray(poses, dtype=float).reshape(-1, 3)
        parents = np.asarray(parents, dtype=np.int64)
        if self.size + len(poses) > len(self.parent):
            parents = self._make_room(len(poses), parents)
        idx = np.arange(self.size, self.size + len(poses))
        self.pose[idx] = poses
        self.parent[idx] = parents
        self.scan[idx] = scan
        self.size += len(poses)
        return idx

    def path(self, node: int) -> np.ndarray:
        """Node indices from the root to ``node`` (inclusive), oldest first."""
        out: list[int] = []
        while node >= 0:
            out.append(int(node))
            node = int(self.parent[node])
        return np.array(out[::-1], dtype=np.int64)

    def trajectory(self, node: int) -> tuple[np.ndarray, np.ndarray]:
        """(scan indices (K,), laser poses (K, 3)) of the nodes with a reading up to ``node``."""
        nodes = self.path(node)
        nodes = nodes[self.scan[nodes] >= 0]
        return self.scan[nodes].copy(), self.pose[nodes].copy()

    # ------------------------------------------------------------------ memory management
    def _make_room(self, extra: int, parents: np.ndarray) -> np.ndarray:
        live = self.size
        if self.size > 2 * self._live_after_compact:
            remap = self.compact(parents)
            parents = remap[parents]
            live = self.size
        need = live + extra
        if need > len(self.parent):
            cap = max(need, 2 * len(self.parent))
            self.pose = np.concatenate([self.pose, np.zeros((cap - len(self.pose), 3))])
            grow = cap - len(self.parent)
            self.parent = np.concatenate([self.parent, np.full(grow, -1, dtype=np.int64)])
            self.scan = np.concatenate([self.scan, np.full(grow, -1, dtype=np.int64)])
        return parents

    def compact(self, keep: np.ndarray) -> np.ndarray:
        """Drop nodes that are not ancestors of ``keep`` (nor in it); returns old → new index
        (−1 for dropped nodes). Callers must remap the node indices they hold."""
        alive = np.zeros(self.size, dtype=bool)
        frontier = np.unique(np.asarray(keep, dtype=np.int64))
        frontier = frontier[frontier >= 0]
        while len(frontier):
            alive[frontier] = True
            frontier = self.parent[frontier]
            frontier = np.unique(frontier[frontier >= 0])
            frontier = frontier[~alive[frontier]]
        alive[0] = True
        old = np.flatnonzero(alive)
        remap = np.full(len(self.parent), -1, dtype=np.int64)
        remap[old] = np.arange(len(old))
        n = len(old)
        self.pose[:n] = self.pose[old]
        parents = self.parent[old]
        self.parent[:n] = np.where(parents >= 0, remap[np.maximum(parents, 0)], -1)
        self.scan[:n] = self.scan[old]
        self.parent[n:] = -1
        self.scan[n:] = -1
        used = set(self.scan[:n][self.scan[:n] >= 0].tolist())
        for index in [k for k in self.readings if k not in used]:
            del self.readings[index]
            self.times.pop(index, None)
        self.size = n
        self._live_after_compact = n
        return remap
