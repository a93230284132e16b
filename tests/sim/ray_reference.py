"""Slow, obviously-correct references for the ray caster and the footprint test.

* :func:`slab_ranges` — exact: for every occupied cell (and the outside of the map), the entry
  distance of the ray into the cell box by the slab method; the minimum wins.
* :func:`geos_ranges` — shapely/GEOS: the ray as a LineString intersected with the union of
  occupied cell boxes; the nearest intersection point.
* :func:`fine_step_ranges` — brute-force stepping along the ray at a small fixed step; the first
  sample inside an occupied cell (or outside the map) bounds the true range from above.
* :func:`footprint_overlap_area` — shapely area of the footprint square ∩ occupied cells.
"""
from __future__ import annotations

import math

import numba
import numpy as np
import shapely
from shapely.geometry import LineString, Polygon, box
from shapely.ops import unary_union

from slam_predict.sim.raycast import GridFrame


def _cell_boxes(occ: np.ndarray, frame: GridFrame):
    """World-frame (xmin, ymin, xmax, ymax) of every occupied cell."""
    rows, cols = np.nonzero(occ)
    res = frame.resolution
    xmin = frame.x_left + cols * res
    ymax = frame.y_top - rows * res
    return xmin, ymax - res, xmin + res, ymax


def slab_ranges(occ, frame: GridFrame, x, y, yaw, angles, range_max) -> np.ndarray:
    """Exact ranges by brute force over all occupied cells (plus the map's outside)."""
    xmin, ymin, xmax, ymax = _cell_boxes(occ, frame)
    rows, cols = occ.shape
    res = frame.resolution
    # the outside of the map: four huge boxes around it
    big = 1e6
    left, top = frame.x_left, frame.y_top
    right, bottom = left + cols * res, top - rows * res
    xmin = np.concatenate([xmin, [-big, right, -big, -big]])
    xmax = np.concatenate([xmax, [left, big, big, big]])
    ymin = np.concatenate([ymin, [-big, -big, top, -big]])
    ymax = np.concatenate([ymax, [big, big, big, bottom]])
    out = np.empty(len(angles))
    with np.errstate(divide="ignore", invalid="ignore"):
        for i, a in enumerate(angles):
            dx, dy = math.cos(yaw + a), math.sin(yaw + a)
            tx1, tx2 = (xmin - x) / dx, (xmax - x) / dx
            ty1, ty2 = (ymin - y) / dy, (ymax - y) / dy
            if dx == 0:
                inside_x = (xmin <= x) & (x < xmax)
                tx1 = np.where(inside_x, -np.inf, np.inf)
                tx2 = np.where(inside_x, np.inf, -np.inf)
            if dy == 0:
                inside_y = (ymin < y) & (y <= ymax)
                ty1 = np.where(inside_y, -np.inf, np.inf)
                ty2 = np.where(inside_y, np.inf, -np.inf)
            t_enter = np.maximum(np.minimum(tx1, tx2), np.minimum(ty1, ty2))
            t_exit = np.minimum(np.maximum(tx1, tx2), np.maximum(ty1, ty2))
            hit = (t_exit >= np.maximum(t_enter, 0.0)) & (t_exit > 0)
            t = np.maximum(t_enter[hit], 0.0).min() if hit.any() else np.inf
            out[i] = min(t, range_max)
    return out


def occupied_geometry(occ, frame: GridFrame):
    """The union of the occupied cell boxes and the map's outside, as one shapely geometry."""
    xmin, ymin, xmax, ymax = _cell_boxes(occ, frame)
    rows, cols = occ.shape
    res = frame.resolution
    outer = box(frame.x_left - 1e3, frame.y_top - rows * res - 1e3,
                frame.x_left + cols * res + 1e3, frame.y_top + 1e3)
    inner = box(frame.x_left, frame.y_top - rows * res, frame.x_left + cols * res, frame.y_top)
    cells = shapely.box(xmin, ymin, xmax, ymax)
    return unary_union(list(cells) + [outer.difference(inner)])


def geos_ranges(geometry, x, y, yaw, angles, range_max) -> np.ndarray:
    """Ranges from GEOS ray/geometry intersections."""
    shapely.prepare(geometry)
    out = np.empty(len(angles))
    for i, a in enumerate(angles):
        end = (x + range_max * math.cos(yaw + a), y + range_max * math.sin(yaw + a))
        hit = LineString([(x, y), end]).intersection(geometry)
        if hit.is_empty:
            out[i] = range_max
            continue
        pts = shapely.get_coordinates(hit)
        out[i] = min(range_max, float(np.hypot(pts[:, 0] - x, pts[:, 1] - y).min()))
    return out


@numba.njit(cache=True)
def fine_step_ranges(occ, x_left, y_top, res, x, y, yaw, angles, range_max, step):
    """First sample (spacing ``step`` m) inside an occupied cell or outside the map."""
    rows, cols = occ.shape
    out = np.empty(angles.shape[0])
    n = int(range_max / step) + 1
    for i in range(angles.shape[0]):
        dx = math.cos(yaw + angles[i])
        dy = math.sin(yaw + angles[i])
        out[i] = range_max
        for k in range(n):
            t = k * step
            if t > range_max:
                break
            col = int(math.floor((x + t * dx - x_left) / res))
            row = int(math.floor((y_top - (y + t * dy)) / res))
            if row < 0 or row >= rows or col < 0 or col >= cols or occ[row, col]:
                out[i] = t
                break
    return out


def footprint_polygon(x, y, yaw, side) -> Polygon:
    """The square footprint as a shapely polygon."""
    h = side / 2.0
    c, s = math.cos(yaw), math.sin(yaw)
    corners = [(x + c * px - s * py, y + s * px + c * py)
               for px, py in ((-h, -h), (h, -h), (h, h), (-h, h))]
    return Polygon(corners)


def footprint_overlap_area(occ, frame: GridFrame, x, y, yaw, side) -> float:
    """Area (m²) of the footprint overlapping occupied cells or the map's outside."""
    foot = footprint_polygon(x, y, yaw, side)
    rows, cols = occ.shape
    res = frame.resolution
    inner = box(frame.x_left, frame.y_top - rows * res, frame.x_left + cols * res, frame.y_top)
    area = foot.difference(inner).area
    minx, miny, maxx, maxy = foot.bounds
    c0 = max(int(math.floor((minx - frame.x_left) / res)) - 1, 0)
    c1 = min(int(math.floor((maxx - frame.x_left) / res)) + 1, cols - 1)
    r0 = max(int(math.floor((frame.y_top - maxy) / res)) - 1, 0)
    r1 = min(int(math.floor((frame.y_top - miny) / res)) + 1, rows - 1)
    for r in range(r0, r1 + 1):
        for c in range(c0, c1 + 1):
            if occ[r, c]:
                cell = box(frame.x_left + c * res, frame.y_top - (r + 1) * res,
                           frame.x_left + (c + 1) * res, frame.y_top - r * res)
                area += foot.intersection(cell).area
    return area
