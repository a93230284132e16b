"""Generated plan → World: area fitting, rasterisation, start pose.

Area: the requested area is the **free floor area** (m²) of the rasterised World — free cells ×
resolution² (``World.free_area_m2``): room and corridor floors minus the walls, plus door
openings. The corridor length is fitted to it: the free area of a plan is estimated exactly from
its geometry (Σ space area − ½·inner wall·Σ space perimeter − ½·(outer − inner wall)·outline
perimeter), the length is rescaled until the estimate is within ``FIT_TOLERANCE``, and the
rasterised area is checked once more (one further correction when it is off by > 2·tolerance).
"""
from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import shapely
from scipy import ndimage

from slam_predict.world import raster
from slam_predict.world.generator.doors import PlannedDoor, plan_doors
from slam_predict.world.generator.params import BuildingParams
from slam_predict.world.generator.plan import Space, band_rooms, corridor_pieces, merge_thin
from slam_predict.world.generator.spine import make_spine
from slam_predict.world.layout_doors import DoorCut
from slam_predict.world.layout_raster import build_canvas, cut_door, keep_largest
from slam_predict.world.model import Door, Room

LOG = logging.getLogger(__name__)
FIT_TOLERANCE = 0.03
MAX_FIT_STEPS = 8


@dataclass
class Plan:
    """A planned building in metres, centred on the origin."""

    shape: str
    spaces: list[Space]
    doors: list[PlannedDoor]
    params: BuildingParams
    length: float

    @property
    def footprint(self):
        """Union of all spaces (shapely)."""
        return shapely.union_all([s.polygon for s in self.spaces])

    def estimated_free_area(self) -> float:
        """Free floor area (m²) the rasterised plan will have (module docstring)."""
        p = self.params
        area = sum(s.polygon.area for s in self.spaces)
        perimeter = sum(s.polygon.exterior.length for s in self.spaces)
        outline = self.footprint.length
        return area - 0.5 * p.wall_inner * perimeter - 0.5 * (p.wall_outer - p.wall_inner) * outline


def make_spaces(params: BuildingParams, length: float, rng: np.random.Generator) -> Plan:
    """Spine → corridors → rooms (no doors yet; not centred)."""
    shape, wings = make_spine(params, length)
    corridors = corridor_pieces(wings, params.corridor_width)
    rooms = merge_thin(band_rooms(wings, corridors, params, rng))
    return Plan(shape, corridors + rooms, [], params, length)


def add_doors(plan: Plan, rng: np.random.Generator) -> Plan:
    """Doors (dropping unreachable rooms), then the plan centred on the origin (m)."""
    spaces = plan.spaces
    doors, dropped = plan_doors(spaces, plan.params, rng)
    if dropped:
        keep = [i for i in range(len(spaces)) if i not in set(dropped)]
        index = {old: new for new, old in enumerate(keep)}
        spaces = [spaces[i] for i in keep]
        for door in doors:
            door.a, door.b = index[door.a], index[door.b]
    x0, y0, x1, y1 = shapely.union_all([s.polygon for s in spaces]).bounds
    shift = np.array([(x0 + x1) / 2.0, (y0 + y1) / 2.0])
    for k, space in enumerate(spaces):
        space.polygon = shapely.affinity.translate(space.polygon, -shift[0], -shift[1])
        space.id = f"{'c' if space.category == 'corridor' else 'r'}{k}"
    for door in doors:
        door.centre = door.centre - shift
    return Plan(plan.shape, spaces, doors, plan.params, plan.length)


def fit_plan(params: BuildingParams, area_m2: float, layout_seed: int) -> Plan:
    """The plan whose estimated free area is closest to ``area_m2`` (rescaling the length)."""
    depth = params.corridor_width + params.depth_left + params.depth_right
    length = area_m2 / (0.85 * depth)
    best = None
    for _ in range(MAX_FIT_STEPS):
        rng = np.random.default_rng(layout_seed)
        plan = make_spaces(params, length, rng)
        estimate = plan.estimated_free_area()
        LOG.debug("corridor length %.1f m: estimated free area %.1f m²", length, estimate)
        if best is None or abs(estimate - area_m2) < abs(best[0] - area_m2):
            best = (estimate, plan, rng)
        if abs(estimate - area_m2) <= FIT_TOLERANCE * area_m2:
            break
        length *= float(np.clip(area_m2 / max(estimate, 1.0), 0.6, 1.6))
    return add_doors(best[1], best[2])


def _outline_segments(footprint) -> np.ndarray:
    rings = []
    for poly in getattr(footprint, "geoms", [footprint]):
        rings += [poly.exterior] + list(poly.interiors)
    segs = [np.stack([np.asarray(r.coords)[:-1], np.asarray(r.coords)[1:]], axis=1)
            for r in rings]
    return np.concatenate(segs)


def door_segment(door: PlannedDoor, wall: float) -> np.ndarray:
    """Ground-truth door segment (2, 2): the opening, or a passage's whole shared wall."""
    half = (door.width + (wall if door.passage else 0.0)) / 2.0
    return np.array([door.centre - door.direction * half, door.centre + door.direction * half])


def rasterise_plan(plan: Plan, resolution: float):
    """(free bitmap, grid, rooms, doors, closed area m²) of a plan."""
    p = plan.params
    rooms = [Room(id=s.id, polygon=np.asarray(s.polygon.exterior.coords)[:-1], label=s.label)
             for s in plan.spaces]
    footprint = plan.footprint
    x0, y0, x1, y1 = footprint.bounds
    grid = raster.Grid.covering(x0, y0, x1, y1, resolution, p.wall_outer + 2 * resolution)
    canvas = build_canvas(rooms, [], grid, p.wall_inner,
                          thick_walls=[(_outline_segments(footprint), p.wall_outer)])
    wall = max(p.wall_inner, p.wall_outer)
    for door in plan.doors:
        cut = DoorCut(door.centre, door.direction, 0.0, door.width,
                      (rooms[door.a].id, rooms[door.b].id))
        if not cut_door(canvas, cut, (door.a + 1, door.b + 1)):
            LOG.warning("generated door %s–%s does not join its rooms", *cut.rooms)
    free, closed = keep_largest(canvas.free, resolution)
    doors = [Door(segment=door_segment(d, wall), rooms=(rooms[d.a].id, rooms[d.b].id))
             for d in plan.doors]
    return free, grid, rooms, doors, closed, canvas.owner


def corridor_start(plan: Plan, free: np.ndarray, owner: np.ndarray, grid: raster.Grid):
    """(x, y, yaw): the cell of largest clearance in the largest corridor, yaw along it."""
    corridors = [(s.polygon.area, k) for k, s in enumerate(plan.spaces)
                 if s.category == "corridor"]
    k = max(corridors)[1]
    rows, cols = np.nonzero((owner == k + 1) & free)
    r0, r1 = max(0, rows.min() - 60), min(grid.rows, rows.max() + 61)
    c0, c1 = max(0, cols.min() - 60), min(grid.cols, cols.max() + 61)
    clearance = ndimage.distance_transform_edt(free[r0:r1, c0:c1])
    clearance[(owner[r0:r1, c0:c1] != k + 1)] = 0
    index = np.unravel_index(int(np.argmax(clearance)), clearance.shape)
    cell = np.array([index[0] + r0, index[1] + c0])
    x = grid.origin[0] + (cell[1] + 0.5 - grid.cols / 2.0) * grid.resolution
    y = grid.origin[1] + (grid.rows / 2.0 - cell[0] - 0.5) * grid.resolution
    bx0, by0, bx1, by1 = plan.spaces[k].polygon.bounds
    yaw = 0.0 if (bx1 - bx0) >= (by1 - by0) else np.pi / 2
    return np.array([x, y, yaw])
