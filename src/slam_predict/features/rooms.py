"""Room (space) segmentation of a floor-plan bitmap, or the World's ground-truth rooms.

``segment`` — a Voronoi / distance-transform segmentation in the spirit of ipa_room_segmentation's
Voronoi method (Bormann et al. 2016), written from its description. It runs on a fixed grid of
``segmentation_resolution_m`` (0.2 m/px; finer maps are resampled, a cell being an obstacle
when any pixel in it is), so that the doorway tests see the same walls whatever resolution the
plan was drawn at (walls rasterised 1 or 2 px thick at 0.1 m/px both become one 0.2 m cell); the
labels are then brought back to the map's own grid (step 6).

1. The building interior (free space inside the outline) and its clearance D (distance to the
   nearest obstacle, m) — :mod:`slam_predict.features.voronoi`.
2. The medial axis of the interior (the cleaned Voronoi skeleton of :mod:`voronoi`).
3. Critical points: skeleton pixels on a simple run (two skeleton neighbours) where the passage
   is narrow (2·D ≤ ``max_door_width_m``) and D is the minimum over the skeleton within
   ``critical_radius_m`` along it, while on *both* sides the skeleton widens to
   D + max(``min_widening_m``, ``widening_ratio``·D) within ``side_search_m`` — a doorway
   between two wider spaces. Candidates closer than the passage width are suppressed (the
   narrowest wins).
4. At each critical point a cut joins its two nearest obstacle points on opposite sides (a
   1-px line, 8-connected, which 4-connected regions cannot cross).
5. Regions = 4-connected free space without the cuts; cut pixels join a neighbouring region;
   regions under ``min_room_area_m2`` merge into the neighbour they share most border with
   (isolated ones are dropped).
6. On a finer map, each pixel takes the label of the coarse cell under it; free pixels under
   coarse obstacle cells take the label reached first by a 4-connected growth inside the
   free space; free space the coarse grid closed off whole (behind a doorway narrower than
   two cells) becomes a room of its own if ≥ ``min_room_area_m2``, else joins the nearest.

``ground_truth`` — the World's rooms (layout XML spaces, generator rooms): each polygon is
rasterised onto the free space; free pixels left out join the nearest room.

The result is a label image (0 = no room, 1..K = rooms) at the World's resolution.
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from typing import ClassVar

import cv2
import numpy as np
from scipy import ndimage

from slam_predict.config import NON_NEGATIVE, POSITIVE, Range
from slam_predict.features import graph_kernels, voronoi
from slam_predict.features.skeleton_graph import pixel_edges, to_csr
from slam_predict.world.bitmap import resample_square
from slam_predict.world.model import World

LOG = logging.getLogger(__name__)
SOURCES = ("segment", "ground_truth")
FOUR = ndimage.generate_binary_structure(2, 1)


@dataclass(frozen=True)
class RoomsConfig:
    """Room segmentation settings (m, m²)."""

    source: str = "segment"
    max_door_width_m: float = 2.6
    critical_radius_m: float = 0.6
    side_search_m: float = 3.0
    min_widening_m: float = 0.25
    widening_ratio: float = 0.25
    min_room_area_m2: float = 1.0
    segmentation_resolution_m: float = 0.2
    RANGES: ClassVar[dict[str, Range]] = {
        "max_door_width_m": POSITIVE, "critical_radius_m": POSITIVE, "side_search_m": NON_NEGATIVE,
        "min_widening_m": NON_NEGATIVE, "widening_ratio": NON_NEGATIVE,
        "min_room_area_m2": NON_NEGATIVE, "segmentation_resolution_m": NON_NEGATIVE}

    def __post_init__(self) -> None:
        if self.source not in SOURCES:
            raise ValueError(f"source must be one of {', '.join(SOURCES)}, got {self.source!r}")
        if self.segmentation_resolution_m < 0:
            raise ValueError("segmentation_resolution_m must be ≥ 0 (0 = the map's own grid)")


@dataclass
class Rooms:
    """A room segmentation: ``labels`` (0 = none, 1..count), ``count``, the critical cuts (px)."""

    labels: np.ndarray
    count: int
    cuts: list[np.ndarray]
    resolution: float

    def masks(self):
        """Yield (label, (row, col) offset, bool mask of the room's bounding box) per room."""
        for k, box in enumerate(ndimage.find_objects(self.labels, self.count), start=1):
            if box is None:
                continue
            yield k, (box[0].start, box[1].start), self.labels[box] == k

    def areas_m2(self) -> np.ndarray:
        """Free area of every room, m² (index k − 1 for label k)."""
        counts = np.bincount(self.labels.ravel(), minlength=self.count + 1)[1:]
        return counts * self.resolution ** 2


def rooms_of(world: World, config: RoomsConfig | None = None,
             base: voronoi.Skeleton | None = None) -> Rooms:
    """Rooms of ``world`` from the configured source (ground truth falls back to segment)."""
    config = config or RoomsConfig()
    if config.source == "ground_truth":
        if world.rooms:
            return ground_truth_rooms(world)
        LOG.warning("%s has no ground-truth rooms: segmenting the bitmap instead", world.name)
    return segment(world.occupied, world.resolution, config, base)


def ground_truth_rooms(world: World) -> Rooms:
    """Label image of the World's ground-truth room polygons (free pixels only)."""
    free = voronoi.building_interior(~world.occupied)
    labels = np.zeros(world.shape, np.int32)
    for k, room in enumerate(world.rooms, start=1):
        rc = world.world_to_cell(np.asarray(room.polygon, float)) if len(room.polygon) else None
        if rc is None or len(rc) < 3:
            continue
        canvas = np.zeros(world.shape, np.uint8)
        cv2.fillPoly(canvas, [rc[:, ::-1].astype(np.int32).reshape(-1, 1, 2)], 1)
        labels[(canvas > 0) & free & (labels == 0)] = k
    labels = _fill_unlabelled(labels, free)
    labels, count = _relabel(labels)
    return Rooms(labels=labels, count=count, cuts=[], resolution=world.resolution)


def segment(occupied: np.ndarray, resolution: float, config: RoomsConfig | None = None,
            base: voronoi.Skeleton | None = None) -> Rooms:
    """Segment the free space of a bitmap (True = obstacle) into rooms (module docstring).

    ``base`` reuses the interior and Voronoi skeleton of :func:`voronoi.skeleton_of` when the
    segmentation runs on the map's own grid.
    """
    config = config or RoomsConfig()
    coarse = config.segmentation_resolution_m
    if coarse <= 0 or resolution >= coarse * (1 - 1e-6):
        return segment_grid(occupied, resolution, config, base)
    size_m = (occupied.shape[1] * resolution, occupied.shape[0] * resolution)
    small = resample_square(occupied, size_m, coarse)
    rooms = segment_grid(small, coarse, config)
    interior = base.interior if base is not None else voronoi.building_interior(~occupied)
    labels = upsample_labels(rooms.labels, interior, config.min_room_area_m2 / resolution ** 2)
    labels, count = _relabel(labels)
    scale = np.array([occupied.shape[0] / small.shape[0], occupied.shape[1] / small.shape[1]])
    cuts = [np.round((cut + 0.5) * scale - 0.5).astype(np.int64) for cut in rooms.cuts]
    return Rooms(labels=labels, count=count, cuts=cuts, resolution=resolution)


def upsample_labels(coarse: np.ndarray, interior: np.ndarray, min_px: float) -> np.ndarray:
    """Labels of a coarse grid on the finer grid of ``interior`` (step 6 of the docstring).

    Free space the coarse grid lost whole (a room behind a doorway narrower than two coarse
    cells) becomes rooms of its own when it has at least ``min_px`` pixels."""
    rows = np.minimum(((np.arange(interior.shape[0]) + 0.5) * coarse.shape[0]
                       / interior.shape[0]).astype(int), coarse.shape[0] - 1)
    cols = np.minimum(((np.arange(interior.shape[1]) + 0.5) * coarse.shape[1]
                       / interior.shape[1]).astype(int), coarse.shape[1] - 1)
    labels = coarse[np.ix_(rows, cols)].astype(np.int32)
    labels[~interior] = 0
    for _ in range(8):  # grow into pixels under coarse obstacles (a few px wide at most)
        missing = interior & (labels == 0)
        if not missing.any():
            break
        grown = ndimage.grey_dilation(labels, footprint=FOUR)
        labels[missing] = grown[missing]
    lost, count = ndimage.label(interior & (labels == 0), structure=FOUR)
    if count:
        sizes = np.bincount(lost.ravel())
        big = np.nonzero(sizes >= min_px)[0]
        big = big[big > 0]
        table = np.zeros(count + 1, np.int32)
        table[big] = int(labels.max()) + 1 + np.arange(big.size)
        labels = np.where(lost > 0, table[lost], labels)
    return _fill_unlabelled(labels, interior)


def segment_grid(occupied: np.ndarray, resolution: float, config: RoomsConfig,
                 base: voronoi.Skeleton | None = None) -> Rooms:
    """Steps 1–5 of the module docstring on the map's own grid."""
    base = base or voronoi.skeleton_of(occupied, resolution)
    interior, site_r, site_c = base.interior, base.site_r, base.site_c
    if not interior.any():
        return Rooms(np.zeros(occupied.shape, np.int32), 0, [], resolution)
    clearance = cv2.distanceTransform(interior.astype(np.uint8), cv2.DIST_L2,
                                      cv2.DIST_MASK_PRECISE).astype(np.float64)
    points = critical_points(base.skeleton, clearance, resolution, config)
    canvas = np.zeros(occupied.shape, np.uint8)
    cuts = []
    for r, c in points:
        line = _cut_line(interior, site_r, site_c, r, c, clearance[r, c])
        if line is None:
            continue
        a, b = line
        if math.hypot(*(a - b)) * resolution > config.max_door_width_m + 2 * resolution:
            continue
        cv2.line(canvas, (int(a[1]), int(a[0])), (int(b[1]), int(b[0])), 1, 1, cv2.LINE_8)
        cuts.append(np.array([a, b]))
    labels, _ = ndimage.label(interior & (canvas == 0), structure=FOUR)
    labels = _fill_unlabelled(labels, interior)
    min_px = config.min_room_area_m2 / resolution ** 2
    labels = merge_small(labels, min_px)
    labels, count = _relabel(labels)
    return Rooms(labels=labels, count=count, cuts=cuts, resolution=resolution)


def critical_points(skeleton: np.ndarray, clearance: np.ndarray, resolution: float,
                    config: RoomsConfig) -> np.ndarray:
    """(K, 2) pixels of doorway critical points on ``skeleton`` (see the module docstring)."""
    index = np.full(skeleton.shape, -1, np.int64)
    rr, cc = np.nonzero(skeleton)
    index[rr, cc] = np.arange(rr.size)
    edges, steps = pixel_edges(skeleton, index, simple=True)
    indptr, indices, weights = to_csr(rr.size, edges, steps)
    dist = clearance[rr, cc]
    found = graph_kernels.critical_candidates(
        indptr, indices, weights, dist, config.max_door_width_m / 2.0 / resolution,
        config.critical_radius_m / resolution, config.side_search_m / resolution,
        config.min_widening_m / resolution, config.widening_ratio)
    order = found[np.argsort(dist[found], kind="stable")]
    chosen = graph_kernels.suppress_neighbours(rr, cc, dist, order, 2.0)
    return np.stack([rr[chosen], cc[chosen]], axis=1).astype(np.int64)


def _cut_line(interior, site_r, site_c, r, c, clearance_px):
    """The two nearest obstacle pixels on opposite sides of (r, c), or None."""
    a = np.array([site_r[r, c], site_c[r, c]])
    va = a - np.array([r, c])
    radius = int(math.ceil(clearance_px * 1.5 + 2))
    r0, r1 = max(r - radius, 0), min(r + radius + 1, interior.shape[0])
    c0, c1 = max(c - radius, 0), min(c + radius + 1, interior.shape[1])
    obst_r, obst_c = np.nonzero(~interior[r0:r1, c0:c1])
    if obst_r.size == 0:
        return None
    vr, vc = obst_r + r0 - r, obst_c + c0 - c
    opposite = vr * va[0] + vc * va[1] < 0
    if not opposite.any():
        return None
    d2 = np.where(opposite, vr ** 2 + vc ** 2, np.iinfo(np.int64).max)
    k = int(np.argmin(d2))
    return a, np.array([vr[k] + r, vc[k] + c])


def _fill_unlabelled(labels: np.ndarray, free: np.ndarray) -> np.ndarray:
    """Give every unlabelled free pixel the label of the nearest labelled pixel."""
    missing = free & (labels == 0)
    if not missing.any() or not (labels > 0).any():
        return labels
    site_r, site_c = voronoi.nearest_site(labels > 0)
    out = labels.copy()
    out[missing] = labels[site_r[missing], site_c[missing]]
    return out


def shared_borders(labels: np.ndarray) -> dict:
    """{(a, b): number of 4-adjacent pixel pairs} between different non-zero labels (a < b)."""
    pairs: dict = {}
    for x, y in ((labels[:, :-1], labels[:, 1:]), (labels[:-1, :], labels[1:, :])):
        sel = (x != y) & (x > 0) & (y > 0)
        a, b = np.minimum(x[sel], y[sel]), np.maximum(x[sel], y[sel])
        if a.size == 0:
            continue
        keys, counts = np.unique(np.stack([a, b], axis=1), axis=0, return_counts=True)
        for (i, j), n in zip(keys, counts, strict=False):
            pairs[(int(i), int(j))] = pairs.get((int(i), int(j)), 0) + int(n)
    return pairs


def merge_small(labels: np.ndarray, min_px: float) -> np.ndarray:
    """Merge regions smaller than ``min_px`` pixels into the neighbour they share most border
    with, smallest region first; small regions without neighbours are dropped (label 0)."""
    areas = np.bincount(labels.ravel()).astype(float)
    adjacency: dict = {k: {} for k in range(1, areas.size)}
    for (a, b), n in shared_borders(labels).items():
        adjacency[a][b] = n
        adjacency[b][a] = n
    parent = np.arange(areas.size)
    while True:
        small = [k for k in adjacency if 0 < areas[k] < min_px]
        if not small:
            break
        k = min(small, key=lambda q: (areas[q], q))
        neighbours = adjacency.pop(k)
        if not neighbours:
            parent[k] = 0
            areas[k] = 0
            continue
        j = max(neighbours, key=lambda q: (neighbours[q], -q))
        parent[k] = j
        areas[j] += areas[k]
        areas[k] = 0
        for q, n in neighbours.items():
            adjacency[q].pop(k, None)
            if q != j:
                adjacency[q][j] = adjacency[q].get(j, 0) + n
                adjacency[j][q] = adjacency[j].get(q, 0) + n
    for k in range(parent.size):  # resolve chains of merges
        root = k
        while parent[root] != root:
            root = parent[root]
        parent[k] = root
    return parent[labels]


def _relabel(labels: np.ndarray):
    """Consecutive labels 1..K in order of first appearance (row-major); returns (labels, K)."""
    present = np.unique(labels[labels > 0])
    table = np.zeros(int(labels.max()) + 1, np.int32)
    table[present] = np.arange(1, present.size + 1)
    return table[labels], int(present.size)
