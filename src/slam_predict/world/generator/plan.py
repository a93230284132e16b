"""From wings to a floor plan: corridor pieces, room bands cut into rooms (shapely, metres).

1. Each wing's corridor is a rectangle ``corridor_width`` wide around its centre line (square
   ends); a wing's corridor *piece* is its rectangle minus those of earlier wings.
2. Each side of a wing carries a band of rooms ``depth`` m deep along the whole corridor; a band
   is clipped by every corridor and by earlier bands (so corners belong to one band).
3. A band is cut across into slots of drawn widths: rooms, small rooms (washrooms, storage)
   and, now and then, a hall (open space, gym, canteen…). Rooms deeper than ``MAX_DEPTH`` are
   split into a front room (on the corridor) and a back room.
4. Parts of rooms narrower than 2·``MIN_HALF_WIDTH`` (slivers left by clipping at junctions)
   are cut off and merged into the neighbour sharing the longest wall with them, when the merged
   room has no narrow part; otherwise they are dropped (left solid). So no room has a neck a
   closed door could pinch off.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry import Polygon, box

from slam_predict.world.generator.params import STYLES, BuildingParams
from slam_predict.world.generator.spine import Wing

MAX_DEPTH = 10.0  # m: deeper band pieces are split into front and back rooms
MIN_HALF_WIDTH = 0.6  # m: a room must contain a disc of this radius
MIN_AREA = 2.5  # m²


@dataclass
class Space:
    """A planned space: polygon (m), label, category ('corridor', 'room', 'small', 'hall')."""

    polygon: Polygon
    label: str
    category: str
    band: int = -1  # index of the band it was cut from (-1: corridor)
    id: str = ""
    meta: dict = field(default_factory=dict)


def _axes(wing: Wing):
    p, q = np.asarray(wing.p, float), np.asarray(wing.q, float)
    u = (q - p) / wing.length
    return p, q, u, np.array([-u[1], u[0]])


def _rect(p, u, n, s0, s1, t0, t1) -> Polygon:
    """The axis-aligned box spanning s0..s1 along u and t0..t1 along n from p (m)."""
    corners = np.array([p + u * s + n * t for s in (s0, s1) for t in (t0, t1)])
    (x0, y0), (x1, y1) = corners.min(axis=0), corners.max(axis=0)
    return box(x0, y0, x1, y1)


def _parts(geom) -> list[Polygon]:
    """The polygons of a shapely result, dropping degenerate slivers."""
    polys = [g for g in getattr(geom, "geoms", [geom]) if isinstance(g, Polygon)]
    return [shapely.normalize(g) for g in polys if g.area > 1e-6]


def corridor_pieces(wings: list[Wing], width: float) -> list[Space]:
    """Step 1 of the module docstring."""
    pieces, taken = [], Polygon()
    for wing in wings:
        p, _, u, n = _axes(wing)
        rect = _rect(p, u, n, -width / 2, wing.length + width / 2, -width / 2, width / 2)
        for part in _parts(rect.difference(taken)):
            if part.area >= MIN_AREA:
                pieces.append(Space(part, "CORRIDOR", "corridor"))
        taken = taken.union(rect)
    return pieces


def _slots(length: float, params: BuildingParams, rng: np.random.Generator) -> list[tuple]:
    """(start, end, category, label) slots along a band of ``length`` m."""
    style = STYLES[params.kind]
    slots, pos = [], 0.0
    while pos < length - 1e-9:
        draw = rng.random()
        if draw < style.hall_prob:
            cat, width, labels = "hall", rng.uniform(*style.hall_width), style.hall_labels
        elif draw < style.hall_prob + style.small_room_prob:
            cat, width, labels = "small", rng.uniform(*style.small_room_width), style.small_labels
        else:
            cat, width, labels = "room", rng.uniform(*style.room_width), style.room_labels
        label = str(labels[int(rng.integers(len(labels)))])
        end = pos + float(width)
        if length - end < style.room_width[0] * 0.6:
            end = length
        slots.append((pos, end, cat, label))
        pos = end
    return slots


def _split_deep(piece: Polygon, p, u, n, side: int, near: float, rng, params) -> list[tuple]:
    """Step 3's depth split: [(polygon, is_front)]."""
    t = np.array([np.dot(np.asarray(c) - p, n) * side for c in piece.exterior.coords])
    if t.max() - near <= MAX_DEPTH:
        return [(piece, True)]
    cut = near + float(rng.uniform(0.55, 0.85)) * STYLES[params.kind].room_depth[1]
    front_zone = _rect(p, u, n * side, -1e4, 1e4, near - 1.0, cut)
    front = _parts(piece.intersection(front_zone))
    back = _parts(piece.difference(front_zone))
    return [(g, True) for g in front] + [(g, False) for g in back]


def band_rooms(wings: list[Wing], corridors: list[Space], params: BuildingParams,
               rng: np.random.Generator) -> list[Space]:
    """Steps 2–3 of the module docstring."""
    style = STYLES[params.kind]
    cw = params.corridor_width
    corridor_union = shapely.union_all([c.polygon for c in corridors])
    taken, rooms, band_index = corridor_union, [], 0
    for wing in wings:
        p, _, u, n = _axes(wing)
        for side, depth in ((1, wing.depth_left), (-1, wing.depth_right)):
            if depth <= 0:
                continue
            t0, t1 = sorted((side * cw / 2, side * (cw / 2 + depth)))
            band = _rect(p, u, n, -cw / 2, wing.length + cw / 2, t0, t1).difference(taken)
            taken = taken.union(band)
            for s0, s1, cat, label in _slots(wing.length + cw, params, rng):
                slab = _rect(p, u, n, s0 - cw / 2, s1 - cw / 2, t0 - 1.0, t1 + 1.0)
                for piece in _parts(band.intersection(slab)):
                    for part, front in _split_deep(piece, p, u, n, side, cw / 2, rng, params):
                        if not front:
                            cat_b = "small" if rng.random() < 0.4 else "room"
                            labels = style.small_labels if cat_b == "small" else style.room_labels
                            rooms.append(Space(part, str(labels[int(rng.integers(len(labels)))]),
                                               cat_b, band_index))
                        else:
                            rooms.append(Space(part, label, cat, band_index))
            band_index += 1
    return rooms


def _opening(poly: Polygon):
    """The polygon without its parts narrower than 2·MIN_HALF_WIDTH (morphological opening)."""
    return poly.buffer(-MIN_HALF_WIDTH, join_style="mitre").buffer(
        MIN_HALF_WIDTH, join_style="mitre").intersection(poly)


def _is_clean(poly: Polygon) -> bool:
    """True when no part of the polygon is narrower than 2·MIN_HALF_WIDTH."""
    return _opening(poly).area >= poly.area - 0.01


def _shared_length(a: Polygon, b: Polygon) -> float:
    return float(a.exterior.intersection(b.buffer(1e-6, join_style="mitre")).length)


def _split_narrow(rooms: list[Space]) -> tuple[list[Space], list[Space]]:
    """(fat rooms, slivers): every room loses its narrow appendages, which become slivers."""
    fat, slivers = [], []
    for room in rooms:
        opened = _parts(_opening(room.polygon))
        if sum(g.area for g in opened) < MIN_AREA:
            slivers.append(room)
            continue
        rest = _parts(room.polygon.difference(shapely.union_all(opened)))
        for k, part in enumerate(sorted(opened, key=lambda g: -g.area)):
            fat.append(Space(part, room.label, room.category, room.band) if k else room)
        room.polygon = max(opened, key=lambda g: g.area)
        slivers += [Space(part, room.label, room.category, room.band) for part in rest]
    return fat, slivers


def merge_thin(rooms: list[Space]) -> list[Space]:
    """Step 4 of the module docstring: narrow appendages and too-thin pieces are merged into
    the neighbour sharing the longest wall with them when the result has no narrow part;
    otherwise they are dropped."""
    fat, slivers = _split_narrow(list(rooms))
    tree = shapely.STRtree([r.polygon for r in fat]) if fat else None
    for sliver in sorted(slivers, key=lambda s: -s.polygon.area):
        if tree is None:
            break
        shared = [(_shared_length(sliver.polygon, fat[int(j)].polygon), int(j))
                  for j in tree.query(sliver.polygon.buffer(1e-3, join_style="mitre"))]
        for length, j in sorted(shared, reverse=True):
            if length < 0.5:
                break
            merged = _parts(shapely.union_all([fat[j].polygon, sliver.polygon]))
            if len(merged) == 1 and _is_clean(merged[0]):
                fat[j].polygon = merged[0]  # the tree keeps the old box: still a neighbour
                break
    return fat
