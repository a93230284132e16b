"""Doors of a layout XML: portal doors (the rule below) and inferred doors on shared walls.

The door rule (the files' PORTAL segments are degenerate: zero length, and in most files the same
single point in both spaces):
1. Portal entries are grouped by the unordered pair of spaces they join. Within a pair, the
   portal points listed by space A are matched to those listed by space B, closest pairs first;
   a matched pair gives one door centred on the midpoint of its two points, an unmatched point a
   door centred on itself (so k portals between two spaces give k doors; duplicates within one
   space, closer than a door width, are merged).
2. The door runs along the shared wall: its direction is, among the outline edges of A and B
   passing within a door width of the centre, the one for which both door ends
   (centre ± width/2 · direction) lie closest to both outlines.
3. The door is the rectangle ``door_width`` long along that direction, cut as deep as needed to
   join the two spaces (:func:`slam_predict.world.layout_raster.cut_door`).

Inferred doors (:func:`shared_wall_door`, used to repair spaces the portals leave cut off) sit
in the middle of the longest stretch of one outline lying within a tolerance of the other.
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import LineString, Point, Polygon

from slam_predict.world.model import Room


@dataclass
class DoorCut:
    """A door to cut: centre (m), unit direction along the wall, gap (m) between the outlines."""

    centre: np.ndarray
    direction: np.ndarray
    gap: float
    width: float
    rooms: tuple[str, str]

    @property
    def segment(self) -> np.ndarray:
        """The door's endpoints (2, 2) in m, along the wall."""
        half = self.direction * self.width / 2.0
        return np.array([self.centre - half, self.centre + half])


def _pair_points(layout, frame) -> dict[tuple[str, str], dict[str, list[np.ndarray]]]:
    """{(a, b) sorted: {space id: [portal points toward the other, world m]}}."""
    pairs: dict[tuple[str, str], dict[str, list[np.ndarray]]] = {}
    known = {s.id for s in layout.spaces}
    for space in layout.spaces:
        for point, other in space.portals:
            if other not in known:
                continue
            key = tuple(sorted((space.id, other)))
            pairs.setdefault(key, {}).setdefault(space.id, []).append(frame.apply(point))
    return pairs


def _dedupe(points: list[np.ndarray], tol: float) -> list[np.ndarray]:
    kept: list[np.ndarray] = []
    for p in points:
        if all(np.hypot(*(p - q)) >= tol for q in kept):
            kept.append(p)
    return kept


def _match(a_pts: list[np.ndarray], b_pts: list[np.ndarray]) -> list[np.ndarray]:
    """Door centres from the two spaces' portal points, closest pairs first."""
    centres = []
    used_a, used_b = set(), set()
    dist = [(float(np.hypot(*(p - q))), i, j) for i, p in enumerate(a_pts)
            for j, q in enumerate(b_pts)]
    for _, i, j in sorted(dist):
        if i in used_a or j in used_b:
            continue
        used_a.add(i)
        used_b.add(j)
        centres.append((a_pts[i] + b_pts[j]) / 2.0)
    centres += [p for i, p in enumerate(a_pts) if i not in used_a]
    centres += [q for j, q in enumerate(b_pts) if j not in used_b]
    return centres


def _edges_near(polygon: np.ndarray, centre: np.ndarray, radius: float) -> list[np.ndarray]:
    """Unit directions of the polygon's edges passing within ``radius`` m of ``centre``."""
    dirs = []
    for p, q in zip(polygon, np.roll(polygon, -1, axis=0), strict=False):
        length = float(np.hypot(*(q - p)))
        if length == 0:
            continue
        t = np.clip(np.dot(centre - p, q - p) / length ** 2, 0.0, 1.0)
        if np.hypot(*(p + t * (q - p) - centre)) <= radius:
            dirs.append((q - p) / length)
    return dirs


def _direction(centre, room_a: Room, room_b: Room, width: float) -> np.ndarray:
    """The wall direction at a door centre (rule 2 of the module docstring)."""
    outlines = [LineString(np.vstack([r.polygon, r.polygon[:1]])) for r in (room_a, room_b)]
    candidates = (_edges_near(room_a.polygon, centre, width)
                  + _edges_near(room_b.polygon, centre, width))
    if not candidates:  # far from both outlines: perpendicular to the line between the rooms
        between = np.asarray(Polygon(room_b.polygon).centroid.coords[0]) - np.asarray(
            Polygon(room_a.polygon).centroid.coords[0])
        norm = float(np.hypot(*between)) or 1.0
        return np.array([-between[1], between[0]]) / norm

    def score(d: np.ndarray) -> float:
        ends = shapely.points(np.array([centre + d * width / 2, centre - d * width / 2]))
        return float(sum(shapely.distance(ends, line).sum() for line in outlines))

    return min(candidates, key=score)


def find_doors(layout, frame, rooms: Sequence[Room], width: float) -> list[DoorCut]:
    """One DoorCut per portal (rules 1-2 of the module docstring); rooms in layout order."""
    by_id = {r.id: r for r in rooms}
    doors = []
    for (a, b), points in sorted(_pair_points(layout, frame).items()):
        a_pts = _dedupe(points.get(a, []), width)
        b_pts = _dedupe(points.get(b, []), width)
        for centre in _dedupe(_match(a_pts, b_pts), width / 2.0):
            room_a, room_b = by_id[a], by_id[b]
            direction = _direction(centre, room_a, room_b, width)
            gap = max(Polygon(r.polygon).exterior.distance(Point(centre))
                      for r in (room_a, room_b))
            doors.append(DoorCut(centre, direction, float(gap), width, (a, b)))
    return doors


CIRCULATION = ("CORRIDOR", "HALL", "LOBBY", "ENTRANCE", "OPENSPACE")


def is_circulation(room: Room) -> bool:
    """True for corridors, halls, lobbies and entrances (where inferred doors prefer to lead)."""
    return any(word in room.label.upper() for word in CIRCULATION)


def shared_wall_door(room_a: Room, room_b: Room, tolerance: float,
                     width: float) -> tuple[float, DoorCut] | None:
    """An inferred door in the middle of the longest stretch of A's outline lying within
    ``tolerance`` m of B's outline: (stretch length m, door), or None when no stretch is at
    least a door width long."""
    outline_a = Polygon(room_a.polygon).exterior
    outline_b = Polygon(room_b.polygon).exterior
    if outline_a.distance(outline_b) > tolerance:
        return None
    shared = outline_a.intersection(outline_b.buffer(tolerance, cap_style="flat"))
    pieces = [g for g in getattr(shared, "geoms", [shared]) if isinstance(g, LineString)]
    pieces = [g for g in pieces if g.length >= width]
    if not pieces:
        return None
    piece = max(pieces, key=lambda g: g.length)
    centre = np.asarray(piece.interpolate(0.5, normalized=True).coords[0])
    before = np.asarray(piece.interpolate(max(0.0, piece.length / 2 - width / 2)).coords[0])
    after = np.asarray(piece.interpolate(min(piece.length, piece.length / 2 + width / 2)).coords[0])
    direction = (after - before) / (float(np.hypot(*(after - before))) or 1.0)
    gap = float(outline_b.distance(Point(centre)))
    return float(piece.length), DoorCut(centre, direction, gap, width, (room_a.id, room_b.id))
