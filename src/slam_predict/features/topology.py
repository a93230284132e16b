"""Topological graph (seed thesis §5.2.2, Algorithms 1–2): spaces = nodes, passages = edges.

Two spaces are directly connected when a flood fill of the free space restricted to the two
of them, started in one, reaches the other (the seed's *selective flood fill*). With every
free pixel labelled by its space this is equivalent to, and computed as: the two label
regions are 4-adjacent along at least ``min_passage_m`` of border (narrower contacts — a
diagonal pixel touch, a crack — are not passages a robot could use).

The graph metrics are taken on the largest connected component, as the seed did.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import cv2
import networkx as nx
import numpy as np

from slam_predict.config import NON_NEGATIVE, Range
from slam_predict.features import graph_metrics
from slam_predict.features.rooms import Rooms, shared_borders
from slam_predict.features.skeleton_graph import largest_component


@dataclass(frozen=True)
class TopologyConfig:
    """Minimum passage width (m) for two spaces to count as connected."""

    min_passage_m: float = 0.3
    RANGES: ClassVar[dict[str, Range]] = {"min_passage_m": NON_NEGATIVE}


@dataclass
class TopologyGraph:
    """Room graph: node k ↔ room label k + 1; ``points`` (K, 2) representative pixels (r, c)."""

    edges: np.ndarray
    points: np.ndarray
    contacts: list[int]

    @property
    def order(self) -> int:
        """Number of rooms (nodes)."""
        return int(self.points.shape[0])

    def to_networkx(self) -> nx.Graph:
        """networkx view (nodes 0..K−1 with attribute ``rc``)."""
        graph = nx.Graph()
        for k, (r, c) in enumerate(self.points):
            graph.add_node(k, rc=(int(r), int(c)))
        graph.add_edges_from(map(tuple, self.edges))
        return graph


def representative_points(rooms: Rooms) -> np.ndarray:
    """For each room, its pixel farthest from the room's border (always inside the room)."""
    points = np.zeros((rooms.count, 2), np.int64)
    for k, (r0, c0), mask in rooms.masks():
        box = np.pad(mask, 1).astype(np.uint8)
        dist = cv2.distanceTransform(box, cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
        r, c = np.unravel_index(int(np.argmax(dist)), dist.shape)
        points[k - 1] = (r0 + r - 1, c0 + c - 1)
    return points


def topology_graph(rooms: Rooms, config: TopologyConfig = TopologyConfig()) -> TopologyGraph:
    """The room graph of a segmentation (module docstring)."""
    min_px = config.min_passage_m / rooms.resolution
    pairs = sorted((pair, n) for pair, n in shared_borders(rooms.labels).items() if n >= min_px)
    edges = np.array([[a - 1, b - 1] for (a, b), _ in pairs], np.int64).reshape(-1, 2)
    return TopologyGraph(edges=edges, points=representative_points(rooms),
                         contacts=[n for _, n in pairs])


def topology_metrics(graph: TopologyGraph) -> dict[str, float]:
    """Graph metrics of the largest connected component of the room graph."""
    n = graph.order
    if n == 0:
        return graph_metrics.metrics(0, graph.edges)
    main = largest_component(n, graph.edges)
    new_id = np.cumsum(main) - 1
    keep = main[graph.edges[:, 0]] & main[graph.edges[:, 1]] if len(graph.edges) else []
    edges = new_id[graph.edges[keep]] if len(graph.edges) else graph.edges
    return graph_metrics.metrics(int(main.sum()), edges)


def room_pairs(graph: TopologyGraph) -> list[tuple[int, int]]:
    """Edges as sorted (room label a, room label b) pairs, labels starting at 1."""
    return sorted((int(a) + 1, int(b) + 1) for a, b in graph.edges)
