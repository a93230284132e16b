"""Geometric features (seed thesis §5.2.1): building outline, walls and spaces.

* The building outline is the longest contour of the free space (the interior of
  :func:`voronoi.building_interior`), traced through boundary pixel centres and simplified by
  Douglas–Peucker with ``outline_tolerance_m``; its area counts every pixel it encloses
  (inner obstacles included), its perimeter is the simplified polygon's length.
* Walls are the edges of a simplified outline at least ``min_wall_m`` long (shorter edges are
  door jambs or pixel noise); the wall ratio is shortest / longest wall.
* Spaces are the rooms of :mod:`rooms`; each one's outline is its largest external contour
  with holes (furniture) filled, measured like the building's.

The seed's code squared the per-space averages (``mean()**2``); here they are plain means.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import cv2
import numpy as np

from slam_predict.config import NON_NEGATIVE, Range
from slam_predict.features.rooms import Rooms


@dataclass(frozen=True)
class GeometryConfig:
    """Outline simplification and minimum wall length, m."""

    outline_tolerance_m: float = 0.1
    min_wall_m: float = 0.5
    RANGES: ClassVar[dict[str, Range]] = {
        "outline_tolerance_m": NON_NEGATIVE, "min_wall_m": NON_NEGATIVE}


@dataclass
class Outline:
    """A simplified outline: polygon (N, 2) in px (x = col, y = row), area m², perimeter m."""

    polygon: np.ndarray
    area: float
    perimeter: float
    wall_ratio: float


def outline_of(mask: np.ndarray, resolution: float, config: GeometryConfig,
               offset=(0, 0)) -> Outline:
    """Outline of the largest external contour of ``mask`` (holes filled); ``offset`` (row, col)
    of the mask in the full bitmap."""
    contours, _ = cv2.findContours(mask.astype(np.uint8), cv2.RETR_EXTERNAL,
                                   cv2.CHAIN_APPROX_NONE, offset=(int(offset[1]), int(offset[0])))
    if not contours:
        return Outline(np.zeros((0, 2)), 0.0, 0.0, 0.0)
    contour = max(contours, key=lambda c: cv2.arcLength(c, True))
    filled = np.zeros(mask.shape, np.uint8)
    cv2.drawContours(filled, [contour], -1, 1, thickness=cv2.FILLED,
                     offset=(-int(offset[1]), -int(offset[0])))
    epsilon = config.outline_tolerance_m / resolution
    poly = cv2.approxPolyDP(contour, epsilon, True).reshape(-1, 2).astype(float)
    perimeter = cv2.arcLength(poly.astype(np.float32).reshape(-1, 1, 2), True) * resolution
    return Outline(polygon=poly, area=float(filled.sum()) * resolution ** 2,
                   perimeter=float(perimeter),
                   wall_ratio=wall_ratio(poly * resolution, config.min_wall_m))


def wall_ratio(polygon_m: np.ndarray, min_wall_m: float) -> float:
    """Shortest / longest edge of a closed polygon (m) among edges ≥ ``min_wall_m``; 0 if none."""
    if len(polygon_m) < 2:
        return 0.0
    edges = np.roll(polygon_m, -1, axis=0) - polygon_m
    lengths = np.hypot(edges[:, 0], edges[:, 1])
    walls = lengths[lengths >= min_wall_m]
    return float(walls.min() / walls.max()) if walls.size else 0.0


def space_outlines(rooms: Rooms, config: GeometryConfig):
    """Outline of every room (holes filled), in label order."""
    return [outline_of(mask, rooms.resolution, config, offset)
            for _, offset, mask in rooms.masks()]


def geometric_features(interior: np.ndarray, rooms: Rooms, resolution: float,
                       config: GeometryConfig = GeometryConfig()) -> dict[str, float]:
    """The eight geometric features (names as in :data:`FEATURES`)."""
    building = outline_of(interior, resolution, config)
    spaces = space_outlines(rooms, config)
    areas = np.array([s.area for s in spaces]) if spaces else np.zeros(1)
    perimeters = np.array([s.perimeter for s in spaces]) if spaces else np.zeros(1)
    ratios = np.array([s.wall_ratio for s in spaces]) if spaces else np.zeros(1)
    return {
        "building_area": building.area,
        "building_perimeter": building.perimeter,
        "wall_ratio": building.wall_ratio,
        "num_spaces": float(len(spaces)),
        "total_space_perimeter": float(perimeters.sum()),
        "avg_space_area": float(areas.mean()),
        "avg_space_perimeter": float(perimeters.mean()),
        "avg_space_wall_ratio": float(ratios.mean()),
    }


# (name, unit, description) of every geometric feature.
FEATURES: tuple[tuple[str, str, str], ...] = (
    ("building_area", "m2", "area enclosed by the building outline (inner obstacles included)"),
    ("building_perimeter", "m", "length of the simplified building outline"),
    ("wall_ratio", "ratio", "shortest / longest wall of the building outline"),
    ("num_spaces", "count", "number of spaces (rooms and corridors)"),
    ("total_space_perimeter", "m", "sum of the space outline lengths"),
    ("avg_space_area", "m2", "mean area of a space (holes filled)"),
    ("avg_space_perimeter", "m", "mean outline length of a space"),
    ("avg_space_wall_ratio", "ratio", "mean shortest / longest wall of a space"),
)
