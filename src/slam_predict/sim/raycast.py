"""Exact ray casting and footprint collision on an occupancy bitmap (numba kernels).

Grid frame: a World's bitmap covers x ∈ [x_left, x_left + cols·res], y ∈ [y_top − rows·res,
y_top]; row 0 is the top. In grid units (cells) a point is gx = (x − x_left)/res,
gy = (y_top − y)/res, in cell (row=floor(gy), col=floor(gx)). Everything outside the bitmap
counts as occupied.

Rays are traversed cell by cell with the Amanatides–Woo voxel walk (no fixed step): the range is
the exact distance to where the ray enters its first occupied cell, ``range_max`` when that is
farther (or nothing is hit), and 0 when the ray starts inside an occupied cell. In open space the
walk leaps ahead by a precomputed safe distance (:func:`jump_table`, from a Euclidean distance
transform) and restarts the walk where it lands; a leap never passes an occupied cell, so the
result is the same as the plain walk's, only faster.
"""
from __future__ import annotations

import math
import weakref
from dataclasses import dataclass

import numba
import numpy as np

_JUMP_CACHE: dict = {}  # id(bitmap) → (weak reference to it, its jump table)
_MIN_LEAP = 3.0  # cells: shorter leaps are not worth restarting the walk


@dataclass(frozen=True)
class GridFrame:
    """Placement of a bitmap in the world: left edge x (m), top edge y (m), cell size (m)."""

    x_left: float
    y_top: float
    resolution: float

    @classmethod
    def of_world(cls, world) -> GridFrame:
        """The frame of a :class:`~slam_predict.world.model.World`'s bitmap."""
        xmin, _, _, ymax = world.extent
        return cls(xmin, ymax, world.resolution)


def jump_table(occ: np.ndarray) -> np.ndarray:
    """Safe jump (cells, float32) from anywhere inside each cell along any direction.

    With D the distance between the cell's centre and the nearest occupied cell's centre
    (the outside of the bitmap counts as occupied), every point of the cell is at least
    D − √2 from every point of every occupied cell, so a ray may advance that far without
    entering one. 0 on occupied cells.
    """
    from scipy import ndimage

    padded = np.pad(~np.asarray(occ, dtype=bool), 1, constant_values=False)
    dist = ndimage.distance_transform_edt(padded)[1:-1, 1:-1]
    return np.maximum(dist - math.sqrt(2.0) - 1e-6, 0.0).astype(np.float32)


def cached_jump_table(occ: np.ndarray) -> np.ndarray:
    """:func:`jump_table` of ``occ``, computed once per bitmap array while it lives (many
    simulators of one World share it; a bitmap must not be modified in place)."""
    entry = _JUMP_CACHE.get(id(occ))
    if entry is not None and entry[0]() is occ:
        return entry[1]
    jump = jump_table(occ)
    _JUMP_CACHE[id(occ)] = (weakref.ref(occ), jump)
    weakref.finalize(occ, _JUMP_CACHE.pop, id(occ), None)
    return jump


@numba.njit(cache=True, nogil=True, inline="always")
def axis_walk(direction, position, cell, t0):
    """Cell walk along one axis from ``position`` (cells, inside ``cell``) at ray parameter t0:
    the cell step (−1, 0, 1), the ray length per cell and the ray parameter at the next cell
    boundary (inf for both when the ray is parallel to that boundary)."""
    if direction > 0.0:
        delta = 1.0 / direction
        return 1, delta, t0 + (cell + 1.0 - position) * delta
    if direction < 0.0:
        delta = -1.0 / direction
        return -1, delta, t0 + (position - cell) * delta
    return 0, math.inf, math.inf


@numba.njit(cache=True, nogil=True, inline="always")
def next_cell(col, row, step_c, step_r, delta_c, delta_r, next_c, next_r):
    """One step of the cell walk, into the neighbour whose boundary the ray crosses first:
    (ray parameter at that boundary, col, row, next_c, next_r)."""
    if next_c < next_r:
        return next_c, col + step_c, row, next_c + delta_c, next_r
    return next_r, col, row + step_r, next_c, next_r + delta_r


@numba.njit(cache=True, nogil=True)
def _ray_cells(occ, jump, gx, gy, dgx, dgy, t_max):
    """Distance in cells along unit direction (dgx, dgy) from (gx, gy) to the first occupied
    cell, or t_max if none is entered before t_max.

    Amanatides–Woo cell walk; where the current cell's ``jump`` is large the walk leaps that
    far along the ray (no occupied cell can lie within it) and restarts from the landing point.
    """
    rows, cols = occ.shape
    t0 = 0.0
    while True:
        px = gx + t0 * dgx
        py = gy + t0 * dgy
        col = int(math.floor(px))
        row = int(math.floor(py))
        if row < 0 or row >= rows or col < 0 or col >= cols or occ[row, col]:
            return t0
        step_c, delta_c, next_c = axis_walk(dgx, px, col, t0)
        step_r, delta_r, next_r = axis_walk(dgy, py, row, t0)
        t = t0
        leap = jump[row, col]
        while leap < _MIN_LEAP:
            t, col, row, next_c, next_r = next_cell(col, row, step_c, step_r, delta_c, delta_r,
                                                    next_c, next_r)
            if t >= t_max:
                return t_max
            if row < 0 or row >= rows or col < 0 or col >= cols or occ[row, col]:
                return t
            leap = jump[row, col]
        # every point of this cell is ≥ leap from any occupied cell: leap from the ray's
        # furthest point inside the cell reached so far (t), then restart the walk there
        t0 = t + leap
        if t0 >= t_max:
            return t_max


@numba.njit(cache=True, nogil=True)
def cast_scan(occ, jump, x_left, y_top, res, px, py, yaw, cos_a, sin_a, range_max, out):
    """Ranges (m) into ``out`` (float32) of beams at bearings whose cos/sin are ``cos_a``,
    ``sin_a`` (laser frame) from a laser at world (px, py) with heading ``yaw`` (rad);
    ``jump`` is :func:`jump_table` of ``occ``."""
    inv = 1.0 / res
    gx = (px - x_left) * inv
    gy = (y_top - py) * inv
    t_max = range_max * inv
    cy = math.cos(yaw)
    sy = math.sin(yaw)
    for i in range(cos_a.shape[0]):
        dx = cy * cos_a[i] - sy * sin_a[i]
        dy = sy * cos_a[i] + cy * sin_a[i]
        t = _ray_cells(occ, jump, gx, gy, dx, -dy, t_max)
        out[i] = range_max if t >= t_max else t * res
    return out


@numba.njit(cache=True, nogil=True)
def _square_overlaps_cell(cx, cy, ux, uy, half, row, col):
    """True when the square (centre (cx, cy), unit axis (ux, uy), half side ``half``, grid
    units) overlaps cell [col, col+1]×[row, row+1] with positive area (separating axes)."""
    lo_u = math.inf
    hi_u = -math.inf
    lo_v = math.inf
    hi_v = -math.inf
    for k in range(4):
        x = col + (k & 1) - cx
        y = row + (k >> 1) - cy
        pu = x * ux + y * uy
        pv = -x * uy + y * ux
        lo_u = min(lo_u, pu)
        hi_u = max(hi_u, pu)
        lo_v = min(lo_v, pv)
        hi_v = max(hi_v, pv)
    return lo_u < half and hi_u > -half and lo_v < half and hi_v > -half


@numba.njit(cache=True, nogil=True)
def footprint_collides(occ, x_left, y_top, res, x, y, yaw, side):
    """True when a square footprint of ``side`` m centred at world (x, y), rotated by ``yaw``,
    overlaps (with positive area) an occupied cell or leaves the bitmap."""
    rows, cols = occ.shape
    inv = 1.0 / res
    cx = (x - x_left) * inv
    cy = (y_top - y) * inv
    half = 0.5 * side * inv
    ux = math.cos(yaw)
    uy = -math.sin(yaw)  # the square's x axis in grid units (y flipped)
    reach = half * (abs(ux) + abs(uy))  # half extent of the axis-aligned bounding box
    c0 = int(math.floor(cx - reach))
    c1 = int(math.ceil(cx + reach)) - 1
    r0 = int(math.floor(cy - reach))
    r1 = int(math.ceil(cy + reach)) - 1
    for row in range(r0, r1 + 1):
        for col in range(c0, c1 + 1):
            inside = 0 <= row < rows and 0 <= col < cols
            if inside and not occ[row, col]:
                continue
            if _square_overlaps_cell(cx, cy, ux, uy, half, row, col):
                return True
    return False


class LaserGrid:
    """An occupancy bitmap ready for ray casting and collision checks (jump table cached).

    Args:
        occupied: bool (rows, cols), True = obstacle.
        frame: where the bitmap lies in the world.
    """

    def __init__(self, occupied: np.ndarray, frame: GridFrame):
        self.occupied = np.ascontiguousarray(occupied, dtype=bool)
        self.frame = frame
        self.jump = cached_jump_table(self.occupied)

    @classmethod
    def of_world(cls, world) -> LaserGrid:
        """The grid of a :class:`~slam_predict.world.model.World`."""
        return cls(world.occupied, GridFrame.of_world(world))

    def scan(self, x: float, y: float, yaw: float, cos_a: np.ndarray, sin_a: np.ndarray,
             range_max: float, out: np.ndarray = None) -> np.ndarray:
        """float32 ranges (m) from a laser at world (x, y, yaw) for beams with bearings
        whose cosines/sines (laser frame) are ``cos_a``/``sin_a``."""
        if out is None:
            out = np.empty(cos_a.shape[0], dtype=np.float32)
        f = self.frame
        return cast_scan(self.occupied, self.jump, f.x_left, f.y_top, f.resolution, float(x),
                         float(y), float(yaw), cos_a, sin_a, float(range_max), out)

    def scan_angles(self, pose, angles: np.ndarray, range_max: float) -> np.ndarray:
        """Convenience: ranges for beams at ``angles`` (rad, laser frame) from laser ``pose``."""
        angles = np.asarray(angles, dtype=float)
        return self.scan(pose[0], pose[1], pose[2], np.cos(angles), np.sin(angles), range_max)

    def collides(self, x: float, y: float, yaw: float, side: float) -> bool:
        """True when a square footprint (side m) at (x, y, yaw) hits an obstacle."""
        f = self.frame
        return bool(footprint_collides(self.occupied, f.x_left, f.y_top, f.resolution,
                                       float(x), float(y), float(yaw), float(side)))


def warmup() -> None:
    """Compile the kernels on a tiny bitmap (fills numba's cache)."""
    occ = np.ones((8, 8), dtype=bool)
    occ[2:6, 2:6] = False
    grid = LaserGrid(occ, GridFrame(0.0, 0.8, 0.1))
    grid.scan_angles((0.4, 0.4, 0.0), np.linspace(-2.0, 2.0, 5), 5.0)
    grid.collides(0.4, 0.4, 0.3, 0.1)
