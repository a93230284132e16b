"""Rasterise a layout (rooms, walls, doors) into free space, opening and repairing doors.

Steps (all on the pixel-centre rule of :mod:`slam_predict.world.raster`):
1. free = union of the room polygons, minus every outline edge and WALL segment drawn
   ``wall_thickness`` m thick (the "walls-only" bitmap; each free cell remembers its room);
2. each door is cut as a rectangle along its wall, as deep as needed to join its two rooms:
   the depth starts at wall thickness + 2·gap + 2 cells and grows cell by cell (up to wall
   thickness + 2·``MAX_GAP``) until the rectangle touches free cells of both rooms — needed
   because neighbouring spaces often draw their shared wall as two lines a few cm apart;
3. repair: while rooms lie in different free components, an *inferred* door is opened in the
   middle of the longest shared wall between two rooms of different components (preferring
   corridors, halls, lobbies and entrances). The data has rooms without any portal, and wings
   whose only portals lead outside; inferred doors are listed in the provenance;
4. free cells still not connected to the largest component (slivers between double walls, or
   rooms sharing no wall with the rest) are closed and their area reported.

:func:`rasterise_sampled` is the *conservative* variant: steps 1–4 run on a grid of samples
``sample_m`` m apart (``k`` x ``k`` samples per cell, ``k = ceil(resolution / sample_m)``) and a
cell is an obstacle when any of its samples is — an obstacle wherever the wall geometry (or the
outside) touches the cell, up to ``sample_m``. The reduction is :func:`bitmap.resample_square`,
the features' working-grid resampler, so rasterising at 0.05 m/px and then resampling to 0.10 m
gives exactly the raster made at 0.10 m/px directly, when both grids share their centre and
extent and the sample lattice is the same (``sample_m`` divides both resolutions).
Step 4 runs on the samples only, so free space joined to the building by a passage narrower
than a cell (a leak at a wall corner) is left as a separate component after the reduction
(``report['free_components']`` > 1), the same at every resolution.
"""
from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from slam_predict.world import raster
from slam_predict.world.bitmap import resample_square
from slam_predict.world.layout_doors import DoorCut, is_circulation, shared_wall_door
from slam_predict.world.model import Room

LOG = logging.getLogger(__name__)
MAX_GAP = 0.6  # m: the widest gap between two outlines a door may bridge
LATTICE_M = 0.1  # m: grid extents are whole multiples of this (nested_cells)
SHARED_WALL_TOLERANCE = 0.35  # m: outlines closer than this share a wall (inferred doors)


@dataclass
class Canvas:
    """The rasterisation state: walls-only free cells, their room (index + 1), current free."""

    grid: raster.Grid
    walls_free: np.ndarray
    owner: np.ndarray
    free: np.ndarray
    wall_thickness: float


def outline_segments(rooms: Sequence[Room]) -> np.ndarray:
    """Every outline edge of every room as segments (N, 2, 2) in m."""
    segs = [np.stack([r.polygon, np.roll(r.polygon, -1, axis=0)], axis=1) for r in rooms]
    return np.concatenate(segs) if segs else np.zeros((0, 2, 2))


def build_canvas(rooms: Sequence[Room], walls: Sequence[np.ndarray], grid: raster.Grid,
                 wall_thickness: float,
                 thick_walls: Sequence[tuple[np.ndarray, float]] = ()) -> Canvas:
    """Step 1 of the module docstring; ``thick_walls`` adds (segments, thickness m) pairs drawn
    with their own thickness (e.g. a generated building's exterior walls)."""
    owner = np.zeros(grid.shape, dtype=np.int32)
    for index, room in enumerate(rooms):
        raster.fill_polygons(owner, grid, [room.polygon], index + 1)
    free = owner > 0
    all_walls = np.concatenate([outline_segments(rooms)]
                               + [np.asarray(w, dtype=float).reshape(-1, 2, 2) for w in walls])
    raster.draw_segments(free, grid, all_walls, wall_thickness, False)
    for segments, thickness in thick_walls:
        raster.draw_segments(free, grid, segments, thickness, False)
    owner[~free] = 0
    return Canvas(grid, free.copy(), owner, free, wall_thickness)


def _door_rect(door: DoorCut, depth: float) -> np.ndarray:
    seg = door.segment
    return raster.segment_rectangle(seg[0], seg[1], depth / 2.0, 0.0)


def _window(canvas: Canvas, polygon: np.ndarray, pad: int = 2) -> tuple[slice, slice]:
    uv = canvas.grid.to_px(polygon)
    r0 = max(0, int(np.floor(uv[:, 1].min())) - pad)
    r1 = min(canvas.grid.rows, int(np.ceil(uv[:, 1].max())) + pad)
    c0 = max(0, int(np.floor(uv[:, 0].min())) - pad)
    c1 = min(canvas.grid.cols, int(np.ceil(uv[:, 0].max())) + pad)
    return slice(r0, max(r0, r1)), slice(c0, max(c0, c1))


def cut_door(canvas: Canvas, door: DoorCut, ids: tuple[int, int], force: bool = True) -> bool:
    """Step 2 of the module docstring; ``ids`` are the two rooms' owner values. Returns whether
    the door joins both rooms (if not, the shallowest rectangle is cut when ``force``)."""
    res, t = canvas.grid.resolution, canvas.wall_thickness
    first = t + 2.0 * door.gap + 2.0 * res
    depths = np.arange(first, max(first, t + 2.0 * MAX_GAP) + res / 2, res)
    rows, cols = _window(canvas, _door_rect(door, depths[-1]))
    sub = canvas.grid.window(rows.start, rows.stop, cols.start, cols.stop)
    walls_free, owner = canvas.walls_free[rows, cols], canvas.owner[rows, cols]
    for depth in depths:
        cut = sub.empty()
        raster.fill_polygons(cut, sub, [_door_rect(door, depth)], True)
        touched = ndimage.binary_dilation(cut, raster.FOUR_CONNECTED) & walls_free
        found = set(np.unique(owner[touched]).tolist())
        if ids[0] in found and ids[1] in found:
            canvas.free[rows, cols] |= cut
            return True
    if not force:
        return False
    cut = sub.empty()
    raster.fill_polygons(cut, sub, [_door_rect(door, depths[0])], True)
    canvas.free[rows, cols] |= cut
    return False


def _room_components(canvas: Canvas, labels: np.ndarray, count: int) -> np.ndarray:
    """For each room (index), the component holding most of its walls-only free cells (0: none)."""
    owners = canvas.owner[canvas.walls_free].astype(np.int64)
    comps = labels[canvas.walls_free].astype(np.int64)
    n_owner = int(canvas.owner.max()) + 1
    table = np.bincount(owners * (count + 1) + comps,
                        minlength=n_owner * (count + 1)).reshape(n_owner, count + 1)
    table[:, 0] = 0
    best = table.argmax(axis=1)
    best[table.max(axis=1) == 0] = 0
    return best[1:]


def _shared_walls(rooms: Sequence[Room], width: float) -> list[tuple[float, int, int, DoorCut]]:
    """Candidate inferred doors (priority, room i, room j, door), best first."""
    import shapely
    from shapely.geometry import Polygon

    polys = [Polygon(r.polygon).buffer(0) for r in rooms]
    tree = shapely.STRtree(polys)
    found = []
    for i, poly in enumerate(polys):
        for j in tree.query(poly.buffer(SHARED_WALL_TOLERANCE)):
            j = int(j)
            if j <= i:
                continue
            hit = shared_wall_door(rooms[i], rooms[j], SHARED_WALL_TOLERANCE, width)
            if hit is not None:
                bonus = 1000.0 if is_circulation(rooms[i]) or is_circulation(rooms[j]) else 0.0
                found.append((hit[0] + bonus, i, j, hit[1]))
    return sorted(found, key=lambda item: -item[0])


def repair(canvas: Canvas, rooms: Sequence[Room], width: float) -> list[DoorCut]:
    """Step 3 of the module docstring: the inferred doors opened."""
    inferred: list[DoorCut] = []
    candidates = None
    while True:
        labels, count = raster.label_free(canvas.free)
        if count <= 1:
            break
        comp = _room_components(canvas, labels, count)
        if len(set(comp[comp > 0].tolist())) <= 1:
            break
        if candidates is None:
            candidates = _shared_walls(rooms, width)
        joined = None
        while candidates and joined is None:
            _, i, j, door = candidates.pop(0)
            if comp[i] > 0 and comp[j] > 0 and comp[i] != comp[j] and cut_door(
                    canvas, door, (i + 1, j + 1), force=False):
                joined = door
        if joined is None:
            break
        inferred.append(joined)
        LOG.info("inferred door between %s and %s", rooms[i].label or rooms[i].id,
                 rooms[j].label or rooms[j].id)
    return inferred


def keep_largest(free: np.ndarray, resolution: float) -> tuple[np.ndarray, float]:
    """Step 4: close every free component but the largest; returns (free, closed area m²)."""
    labels, count = raster.label_free(free)
    if count <= 1:
        return free, 0.0
    sizes = np.bincount(labels.ravel())
    sizes[0] = 0
    keep = labels == int(np.argmax(sizes))
    closed = float((free & ~keep).sum()) * resolution ** 2
    LOG.info("%d free islands unreachable from the main building closed (%.2f m²)",
             count - 1, closed)
    return keep, closed


def rasterise(rooms: Sequence[Room], walls: Sequence[np.ndarray], doors: Sequence[DoorCut],
              grid: raster.Grid, wall_thickness: float, door_width: float):
    """Free-space bitmap of a layout: (free, inferred doors, report dict)."""
    canvas = build_canvas(rooms, walls, grid, wall_thickness)
    index = {r.id: i + 1 for i, r in enumerate(rooms)}
    unjoined = [d for d in doors if not cut_door(canvas, d, (index[d.rooms[0]],
                                                             index[d.rooms[1]]))]
    inferred = repair(canvas, rooms, door_width)
    free, closed = keep_largest(canvas.free, grid.resolution)
    reached = np.bincount(canvas.owner[free & canvas.walls_free], minlength=len(rooms) + 1)
    report = {"closed_islands_m2": round(closed, 3), "portals_not_joined": len(unjoined),
              "inferred_doors": [list(d.rooms) for d in inferred],
              "rooms_closed": [r.id for r, n in zip(rooms, reached[1:], strict=False) if n == 0]}
    return free, inferred, report


def nested_cells(size_m: float, resolution: float, ceil: bool = False) -> int:
    """Cells of ``resolution`` m along an axis of ``size_m`` m (rounded, or rounded up with
    ``ceil``). When ``resolution`` divides LATTICE_M the size is first rounded to whole
    LATTICE_M cells, so that grids at 0.05 and 0.10 m/px centred on the same origin span the
    same extent and every 0.10 m cell is exactly 2 x 2 cells of 0.05 m."""
    step = resolution
    ratio = LATTICE_M / resolution
    if resolution <= LATTICE_M and abs(ratio - round(ratio)) < 1e-6:
        step = LATTICE_M
    cells = size_m / step
    cells = int(np.ceil(cells - 1e-9)) if ceil else int(round(cells))
    return max(1, cells) * max(1, int(round(step / resolution)))


def samples_per_cell(resolution: float, sample_m: float) -> int:
    """k = ceil(resolution / sample_m) (≥ 1), tolerant of floating-point ratios like 0.1/0.05."""
    return max(1, int(np.ceil(resolution / sample_m - 1e-6)))


def rasterise_sampled(rooms: Sequence[Room], walls: Sequence[np.ndarray],
                      doors: Sequence[DoorCut], grid: raster.Grid, wall_thickness: float,
                      door_width: float, sample_m: float):
    """Conservative free-space bitmap (module docstring): :func:`rasterise` on ``sample_m``
    samples, then a cell is free only when all its samples are. Same return values."""
    k = samples_per_cell(grid.resolution, sample_m)
    if k == 1:
        return rasterise(rooms, walls, doors, grid, wall_thickness, door_width)
    fine = raster.Grid(grid.rows * k, grid.cols * k, grid.resolution / k, grid.origin)
    free, inferred, report = rasterise(rooms, walls, doors, fine, wall_thickness, door_width)
    size_m = (grid.cols * grid.resolution, grid.rows * grid.resolution)
    free = ~resample_square(~free, size_m, grid.resolution)
    # no second keep_largest: the result must depend on the samples only (not on k), so free
    # space joined only through a passage narrower than a cell stays as its own component
    report.update(samples_per_cell=k, free_components=raster.label_free(free)[1])
    return free, inferred, report
