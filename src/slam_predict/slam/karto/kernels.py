"""numba kernels of Karto's correlative scan matcher (ScanMatcher, CorrelationGrid,
GridIndexLookup): grid cells are addressed as Karto does, ``x + y * width_step`` in one flat
uint8 array (width_step = width rounded up to a multiple of 8)."""
from __future__ import annotations

import math

import numpy as np
from numba import njit

OCCUPIED = 100          # GridStates_Occupied
INVALID_SCAN = np.iinfo(np.int64).max   # Karto's INVALID_SCAN marker of a lookup offset
DISTANCE_PENALTY_GAIN = 0.2
ANGLE_PENALTY_GAIN = 0.2


@njit(cache=True)
def karto_round(value: float) -> float:
    """Karto's math::Round: halves away from zero."""
    return math.floor(value + 0.5) if value >= 0.0 else math.ceil(value - 0.5)


@njit(cache=True)
def to_grid(value: float, offset: float, resolution: float) -> int:
    """CoordinateConverter::WorldToGrid on one axis: (value − offset) × (1 / resolution),
    rounded (Karto multiplies by its stored scale)."""
    return int(karto_round((value - offset) * (1.0 / resolution)))


@njit(cache=True)
def valid_points(points: np.ndarray, view_x: float, view_y: float) -> np.ndarray:
    """ScanMatcher::FindValidPoints: the points (N, 2) m seen from the side of the view point
    (the running scan's points facing away from it dropped); order kept."""
    keep = np.zeros(points.shape[0], np.bool_)
    trailing = 0
    first_x = 0.0
    first_y = 0.0
    first_time = True
    for k in range(points.shape[0]):
        cx, cy = points[k, 0], points[k, 1]
        if first_time and not (math.isnan(cx) or math.isnan(cy)):
            first_x, first_y = cx, cy
            first_time = False
        dx, dy = first_x - cx, first_y - cy
        if dx * dx + dy * dy > 0.01:
            a = view_y - first_y
            b = first_x - view_x
            c = first_y * view_x - first_x * view_y
            ss = cx * a + cy * b + c
            first_x, first_y = cx, cy
            if ss < 0.0:
                trailing = k
            else:
                while trailing < k:
                    keep[trailing] = True
                    trailing += 1
    return keep


@njit(cache=True)
def add_points(grid, width_step, roi, points, offset_x, offset_y, resolution, kernel):
    """CorrelationGrid::AddScan for the valid points (N, 2) of one scan: mark the cell of each
    point inside the ROI (x, y, w, h cells) occupied and smear the kernel around it."""
    half = kernel.shape[0] // 2
    for k in range(points.shape[0]):
        px, py = points[k, 0], points[k, 1]
        if not (math.isfinite(px) and math.isfinite(py)):
            continue
        gx = to_grid(px, offset_x, resolution)
        gy = to_grid(py, offset_y, resolution)
        if gx < 0 or gx >= roi[2] or gy < 0 or gy >= roi[3]:
            continue
        index = (gx + roi[0]) + (gy + roi[1]) * width_step
        if grid[index] == OCCUPIED:
            continue
        grid[index] = OCCUPIED
        for j in range(-half, half + 1):
            row = (gx + roi[0]) + (gy + j + roi[1]) * width_step
            for i in range(-half, half + 1):
                value = kernel[j + half, i + half]
                if value > grid[row + i]:
                    grid[row + i] = value


@njit(cache=True)
def lookup_offsets(local, finite, angles, offset_x, offset_y, resolution, width_step):
    """GridIndexLookup::ComputeOffsets: per angle (A) and point (N) the flat-index offset of the
    point rotated by the angle (INVALID_SCAN where the k-th range reading is not finite)."""
    out = np.empty((angles.shape[0], local.shape[0]), np.int64)
    for a in range(angles.shape[0]):
        cosine, sine = math.cos(angles[a]), math.sin(angles[a])
        for k in range(local.shape[0]):
            if not finite[k]:
                out[a, k] = INVALID_SCAN
                continue
            ox = cosine * local[k, 0] - sine * local[k, 1]
            oy = sine * local[k, 0] + cosine * local[k, 1]
            gx = to_grid((ox + offset_x), offset_x, resolution)
            gy = to_grid((oy + offset_y), offset_y, resolution)
            out[a, k] = gx + gy * width_step
    return out


@njit(cache=True)
def response_at(grid, offsets, angle_index, grid_index):
    """ScanMatcher::GetResponse: mean smeared value under the rotated points, in [0, 1]."""
    n = offsets.shape[1]
    if n == 0:
        return 0.0
    total = 0.0
    size = grid.shape[0]
    for k in range(n):
        off = offsets[angle_index, k]
        if off == INVALID_SCAN:
            continue
        index = grid_index + off
        if index < 0 or index >= size:
            continue
        total += grid[index]
    return total / (n * OCCUPIED)


@njit(cache=True)
def correlate(grid, width_step, roi, offset_x, offset_y, resolution, offsets, center, xs, ys,
              angles, penalize, penalty):
    """The response (nY, nX, nA) of every candidate pose of ScanMatcher::CorrelateScan;
    ``penalty`` = (distance_variance_penalty, minimum_distance_penalty, angle_variance_penalty,
    minimum_angle_penalty)."""
    out = np.zeros((ys.shape[0], xs.shape[0], angles.shape[0]))
    for iy in range(ys.shape[0]):
        y = ys[iy]
        for ix in range(xs.shape[0]):
            x = xs[ix]
            gx = to_grid(center[0] + x, offset_x, resolution)
            gy = to_grid(center[1] + y, offset_y, resolution)
            grid_index = (gx + roi[0]) + (gy + roi[1]) * width_step
            for a in range(angles.shape[0]):
                response = response_at(grid, offsets, a, grid_index)
                if penalize and abs(response) >= 1e-6:
                    distance = 1.0 - DISTANCE_PENALTY_GAIN * (x * x + y * y) / penalty[0]
                    distance = max(distance, penalty[1])
                    turn = angles[a] - center[2]
                    angular = 1.0 - ANGLE_PENALTY_GAIN * turn * turn / penalty[2]
                    angular = max(angular, penalty[3])
                    response *= distance * angular
                out[iy, ix, a] = response
    return out
