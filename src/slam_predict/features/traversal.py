"""Voronoi traversal distance and rotation (seed thesis §5.2.3.2, Algorithms 3–4).

A virtual robot with a laser (range ``laser_range_m`` m, field of view ``laser_fov`` rad; a robot's
own laser with :meth:`TraversalConfig.for_laser`) starts
at the Voronoi node nearest the world's start pose, facing the start yaw, and alternates:

* mapping: every unseen graph node within range, inside the field of view around the current
  heading, and with a free digital line of sight (:mod:`kernels`) becomes seen;
* moving: the unseen node nearest the robot (Euclidean, ties to the lowest row-major index) is
  the next frontier; the robot follows the shortest graph path to it, and at every node of the
  path it adds the step length to the distance, updates its heading to the step direction and
  maps again. The rotation adds |heading change| between anchor points whose path distance
  exceeds ``min_rotation_distance_m`` (0.5 m), so pixel jitter is not counted.

It stops when every node has been seen. Beyond the thesis: ``rotation_smoothed`` is the summed
absolute turning of the path simplified by Douglas–Peucker with ``smoothing_tolerance_m``.

Presets (``mode``):

* ``documented`` (default) — the algorithm as the thesis text describes it: Dijkstra on edge
  lengths, the heading kept when the robot does not move.
* ``thesis_compatible`` — what the seed's code (``predictor/analyzer.py``) does, which is what
  produced the published ``Voronoi distance`` column: fewest-hops paths (networkx
  ``shortest_path`` without weights) on the sparsified graph with unit pixel weights, the
  first scan facing north and the rotation counted from east whatever the start yaw, and the
  heading reset to east for the scan at the first node of every path. Use it together with
  ``VoronoiConfig(thesis_compatible=True)``.
"""
from __future__ import annotations

import dataclasses
import logging
import math
from dataclasses import dataclass
from typing import Any, ClassVar

import cv2
import numpy as np

from slam_predict.config import NON_NEGATIVE, POSITIVE, Range
from slam_predict.features import kernels
from slam_predict.features.polyline import douglas_peucker
from slam_predict.features.voronoi import VoronoiGraph
from slam_predict.sensor import DEFAULT_FOV, FULL_TURN, LaserConfig

LOG = logging.getLogger(__name__)

MODES = ("documented", "thesis_compatible")


@dataclass(frozen=True)
class TraversalConfig:
    """Traversal settings (m, rad). ``laser_fov`` defaults to 270 ° (4.71238898038469 rad);
    ``laser_fov_deg`` is its deprecated degree form (still read, with a warning)."""

    laser_range_m: float = 30.0
    laser_fov: float | None = None
    laser_fov_deg: float | None = None
    min_rotation_distance_m: float = 0.5
    smoothing_tolerance_m: float = 0.5
    mode: str = "documented"
    RANGES: ClassVar[dict[str, Range]] = {
        "laser_range_m": POSITIVE, "laser_fov": FULL_TURN,
        "laser_fov_deg": Range(0.0, 360.0, open_low=True),
        "min_rotation_distance_m": NON_NEGATIVE, "smoothing_tolerance_m": NON_NEGATIVE}

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise ValueError(f"mode must be one of {', '.join(MODES)}, got {self.mode!r}")
        if self.laser_fov_deg is not None:
            if self.laser_fov is not None:
                raise ValueError("give laser_fov (rad) or the deprecated laser_fov_deg, not both")
            LOG.warning("traversal laser_fov_deg is deprecated: write laser_fov: %r (rad)",
                        math.radians(self.laser_fov_deg))
            object.__setattr__(self, "laser_fov", math.radians(self.laser_fov_deg))
            object.__setattr__(self, "laser_fov_deg", None)
        if self.laser_fov is None:
            object.__setattr__(self, "laser_fov", DEFAULT_FOV)
        if self.laser_range_m <= 0 or not 0 < self.laser_fov <= 2 * math.pi:
            raise ValueError("laser_range_m must be > 0 and laser_fov in (0, 2*pi] rad")

    def for_laser(self, laser: LaserConfig, max_range: float | None = None
                  ) -> TraversalConfig:
        """These settings with a robot's laser: its fov and its range_max, capped at
        ``max_range`` m when given (the range the mapping uses, e.g. GMapping's maxUrange)."""
        reach = laser.range_max if max_range is None else min(laser.range_max, max_range)
        return dataclasses.replace(self, laser_range_m=float(reach), laser_fov=float(laser.fov))


def upgrade_stored(traversal: dict[str, Any]) -> dict[str, Any]:
    """Stored traversal settings (a model card's, written before ``laser_fov``) with
    ``laser_fov_deg`` turned into ``laser_fov`` rad, without the deprecation warning."""
    out = dict(traversal)
    degrees = out.pop("laser_fov_deg", None)
    if degrees is not None and out.get("laser_fov") is None:
        out["laser_fov"] = math.radians(float(degrees))
    elif degrees is not None:
        out["laser_fov_deg"] = degrees   # both given: let the config refuse it
    return out


def legacy_hash_form(traversal: dict[str, Any]) -> dict[str, Any]:
    """The plain-dict traversal settings as they were hashed into the feature version before
    the field of view became ``laser_fov`` (rad): ``laser_fov_deg`` in degrees (rounded to
    1e-9 °), so models trained before the change keep their feature version."""
    out = {k: v for k, v in traversal.items() if k not in ("laser_fov", "laser_fov_deg")}
    out["laser_fov_deg"] = round(math.degrees(traversal["laser_fov"]), 9)
    return out


@dataclass
class TraversalResult:
    """Outcome of a traversal.

    Attributes:
        distance: path length, m.
        rotation: summed absolute heading change (thesis rule), rad.
        rotation_smoothed: summed absolute turning of the simplified path, rad.
        path_rc: (K, 2) visited node pixels (row, col) in order.
        start_node: index of the start node in the graph.
        scans: number of mapping phases.
    """

    distance: float
    rotation: float
    rotation_smoothed: float
    path_rc: np.ndarray
    start_node: int
    scans: int


def nearest_node(graph: VoronoiGraph, rc) -> int:
    """Index of the graph node nearest (Euclidean, px) to pixel ``rc``; ties to the lowest index."""
    d2 = ((graph.rc - np.asarray(rc, dtype=float)) ** 2).sum(axis=1)
    return int(np.argmin(d2))


def traverse(graph: VoronoiGraph, occupied: np.ndarray, start_rc, start_yaw: float = 0.0,
             config: TraversalConfig | None = None) -> TraversalResult:
    """Run the Voronoi traversal from pixel ``start_rc`` with heading ``start_yaw`` (rad)."""
    config = config or TraversalConfig()
    if graph.order == 0:
        return TraversalResult(0.0, 0.0, 0.0, np.zeros((0, 2), np.int64), -1, 0)
    res = graph.resolution
    indptr, indices, weights = graph.csr()
    start = nearest_node(graph, start_rc)
    compat = config.mode == "thesis_compatible"
    occupied = np.ascontiguousarray(occupied, dtype=np.bool_)
    visits, dist_px, rotation, scans = kernels.traverse(
        occupied, clearance_px(occupied), graph.rc[:, 0].copy(),
        graph.rc[:, 1].copy(), indptr, indices, weights, start,
        math.pi / 2 if compat else float(start_yaw), 0.0 if compat else float(start_yaw),
        config.laser_range_m / res,
        config.laser_fov / 2.0, config.min_rotation_distance_m / res,
        compat, compat)
    path_rc = graph.rc[visits]
    smoothed = polyline_turning(simplify_polyline(path_rc * res, config.smoothing_tolerance_m))
    return TraversalResult(distance=float(dist_px * res), rotation=float(rotation),
                           rotation_smoothed=smoothed, path_rc=path_rc, start_node=start,
                           scans=int(scans))


def clearance_px(occupied: np.ndarray) -> np.ndarray:
    """Euclidean distance (px, float64) from each pixel centre to the nearest occupied centre."""
    if not occupied.any():
        return np.full(occupied.shape, np.inf)
    dist = cv2.distanceTransform((~occupied).astype(np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
    return dist.astype(np.float64)


def simplify_polyline(points: np.ndarray, tolerance: float) -> np.ndarray:
    """Douglas–Peucker simplification of an open polyline (N, 2) with ``tolerance`` (same unit).

    Iterative; keeps the first and last points. Revisits (back-and-forth paths) are kept as
    turns because every point is compared with its own chord.
    """
    points = np.asarray(points, dtype=float)
    n = len(points)
    if n < 3 or tolerance <= 0:
        return points
    return points[douglas_peucker(points, tolerance)]


def polyline_turning(points: np.ndarray) -> float:
    """Sum of absolute heading changes (rad) between consecutive non-zero segments."""
    if len(points) < 3:
        return 0.0
    steps = np.diff(points, axis=0)
    steps = steps[np.hypot(steps[:, 0], steps[:, 1]) > 0]
    if len(steps) < 2:
        return 0.0
    angles = np.arctan2(steps[:, 1], steps[:, 0])
    turns = np.angle(np.exp(1j * np.diff(angles)))
    return float(np.abs(turns).sum())
