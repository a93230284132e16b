"""Doors of a generated plan: room → corridor doors, corridor passages, suites.

Rules (m):
- corridor pieces that share a wall are joined by a *passage*: an opening over the whole shared
  wall (the ground-truth door is the shared segment; the cut keeps the end walls intact);
- every room gets a door (halls: two when the wall is long enough) onto the corridor with which
  it shares the longest straight wall; the door is at a random place at least
  width/2 + wall + ``CORNER_GAP`` from both ends of that wall;
- a room without a corridor wall gets a door to a neighbouring room already reachable (a suite);
  rooms that cannot be reached that way are dropped;
- with a style's ``suite_door_prob``, two neighbouring reachable rooms get an extra door.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import LineString, Polygon

from slam_predict.world.generator.params import STYLES, BuildingParams
from slam_predict.world.generator.plan import Space

CORNER_GAP = 0.4


@dataclass
class PlannedDoor:
    """A door between spaces ``a`` and ``b`` (indices): centre, unit direction along the wall,
    width (m); ``passage`` doors open the whole shared wall of two corridor pieces."""

    a: int
    b: int
    centre: np.ndarray
    direction: np.ndarray
    width: float
    passage: bool = False


def shared_segments(a: Polygon, b: Polygon, min_length: float) -> list[tuple[np.ndarray,
                                                                               np.ndarray]]:
    """Straight pieces (p, q) of A's outline lying on B's outline, at least ``min_length`` m."""
    shared = a.exterior.intersection(b.buffer(1e-6, join_style="mitre"))
    lines = [g for g in getattr(shared, "geoms", [shared]) if isinstance(g, LineString)]
    merged = shapely.line_merge(shapely.union_all(lines)) if lines else None
    out = []
    for line in ([] if merged is None else getattr(merged, "geoms", [merged])):
        if isinstance(line, LineString):
            out += [(p, q) for p, q in _straight_runs(np.asarray(line.coords))
                    if np.hypot(*(q - p)) >= min_length]
    return out


def _straight_runs(coords: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """A polyline split into its straight runs (p, q) (collinear vertices merged)."""
    runs, start = [], 0
    for k in range(1, len(coords) - 1):
        before = coords[k] - coords[start]
        after = coords[k + 1] - coords[k]
        norm = float(np.hypot(*before) * np.hypot(*after)) or 1.0
        cross = before[0] * after[1] - before[1] * after[0]
        if abs(float(cross)) / norm > 1e-6 or np.dot(before, after) < 0:
            runs.append((coords[start], coords[k]))
            start = k
    runs.append((coords[start], coords[-1]))
    return runs


def _place(seg, width: float, wall: float, rng, fraction: tuple[float, float] | None = None):
    """(centre, direction) of a door on segment ``seg`` or None when it does not fit."""
    p, q = seg
    length = float(np.hypot(*(q - p)))
    margin = width / 2 + wall + CORNER_GAP
    lo, hi = margin, length - margin
    if fraction is not None:
        lo, hi = max(lo, fraction[0] * length), min(hi, fraction[1] * length)
    if hi < lo:
        return None
    d = (q - p) / length
    return p + d * float(rng.uniform(lo, hi)), d


def _neighbours(spaces: list[Space]) -> dict[int, list[int]]:
    tree = shapely.STRtree([s.polygon for s in spaces])
    out: dict[int, list[int]] = {i: [] for i in range(len(spaces))}
    for i, space in enumerate(spaces):
        for j in tree.query(space.polygon.buffer(1e-3, join_style="mitre")):
            if int(j) != i:
                out[i].append(int(j))
    return out


def _best_wall(spaces, i, candidates, min_length):
    best = None
    for j in candidates:
        for seg in shared_segments(spaces[i].polygon, spaces[j].polygon, min_length):
            length = float(np.hypot(*(seg[1] - seg[0])))
            if best is None or length > best[0]:
                best = (length, j, seg)
    return best


def plan_doors(spaces: list[Space], params: BuildingParams,
               rng: np.random.Generator) -> tuple[list[PlannedDoor], list[int]]:
    """(doors, indices of dropped spaces) by the rules of the module docstring."""
    style, wall = STYLES[params.kind], max(params.wall_inner, params.wall_outer)
    near = _neighbours(spaces)
    corridors = [i for i, s in enumerate(spaces) if s.category == "corridor"]
    doors: list[PlannedDoor] = []
    for i in corridors:
        for j in near[i]:
            if j > i and spaces[j].category == "corridor":
                for p, q in shared_segments(spaces[i].polygon, spaces[j].polygon, 1.0):
                    length = float(np.hypot(*(q - p)))
                    doors.append(PlannedDoor(i, j, (p + q) / 2, (q - p) / length,
                                             length - wall, passage=True))
    reached = set(corridors)
    pending = [i for i, s in enumerate(spaces) if s.category != "corridor"]
    for i in pending:
        hall = spaces[i].category == "hall"
        width = float(rng.uniform(*(style.hall_door_width if hall else style.door_width)))
        best = _best_wall(spaces, i, [j for j in near[i] if j in corridors], width + 2 * wall)
        if best is None:
            continue
        spots = [(0.0, 0.5), (0.5, 1.0)] if hall and best[0] > 4 * width + 4 * wall else [None]
        for spot in spots:
            placed = _place(best[2], width, wall, rng, spot)
            if placed is not None:
                doors.append(PlannedDoor(i, best[1], placed[0], placed[1], width))
                reached.add(i)
    changed = True
    while changed:  # suites: rooms reached through a reachable neighbour
        changed = False
        for i in pending:
            if i in reached:
                continue
            width = float(rng.uniform(*style.door_width))
            best = _best_wall(spaces, i, [j for j in near[i] if j in reached], width + 2 * wall)
            placed = None if best is None else _place(best[2], width, wall, rng)
            if placed is not None:
                doors.append(PlannedDoor(i, best[1], placed[0], placed[1], width))
                reached.add(i)
                changed = True
    joined = {frozenset((d.a, d.b)) for d in doors}
    rooms = set(pending)
    for i in pending:
        for j in near[i]:
            if j > i and j in rooms and i in reached and j in reached \
                    and frozenset((i, j)) not in joined and rng.random() < style.suite_door_prob:
                width = float(rng.uniform(*style.door_width))
                best = _best_wall(spaces, i, [j], width + 2 * wall)
                placed = None if best is None else _place(best[2], width, wall, rng)
                if placed is not None:
                    doors.append(PlannedDoor(i, j, placed[0], placed[1], width))
    dropped = [i for i in range(len(spaces)) if i not in reached]
    return doors, dropped
