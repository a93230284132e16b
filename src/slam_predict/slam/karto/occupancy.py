"""Karto's OccupancyGrid::CreateFromScans: pass and hit counts of every scan's beams (Bresenham
lines from the sensor), then a cell is occupied when passed more than ``min_pass_through``
times with hits/passes above ``occupancy_threshold``, free when passed that often otherwise."""
from __future__ import annotations

import math

import numpy as np
from numba import njit

UNKNOWN, FREE, OCCUPIED = -1, 0, 100


@njit(cache=True)
def _round(value):
    return int(math.floor(value + 0.5))


@njit(cache=True)
def trace_line(passes, x0, y0, x1, y1):
    """Grid::TraceLine: add a pass to every valid cell of the Bresenham line, both ends in."""
    steep = abs(y1 - y0) > abs(x1 - x0)
    if steep:
        x0, y0, x1, y1 = y0, x0, y1, x1
    if x0 > x1:
        x0, x1, y0, y1 = x1, x0, y1, y0
    delta_x, delta_y = x1 - x0, abs(y1 - y0)
    error = 0
    ystep = 1 if y0 < y1 else -1
    y = y0
    height, width = passes.shape
    for x in range(x0, x1 + 1):
        px, py = (y, x) if steep else (x, y)
        error += delta_y
        if 2 * error >= delta_x:
            y += ystep
            error -= delta_x
        if 0 <= px < width and 0 <= py < height:
            passes[py, px] += 1


@njit(cache=True)
def add_scan(passes, hits, offset_x, offset_y, resolution, sensor, points, ranges,
             minimum_range, maximum_range, range_threshold):
    """OccupancyGrid::AddScan: trace every reading in (min, max) range, cut at the threshold;
    the end cell gets a hit when the reading is below the threshold."""
    sx = _round((sensor[0] - offset_x) / resolution)
    sy = _round((sensor[1] - offset_y) / resolution)
    height, width = passes.shape
    for k in range(ranges.shape[0]):
        r = ranges[k]
        if math.isnan(r) or r <= minimum_range or r >= maximum_range:
            continue
        px, py = points[k, 0], points[k, 1]
        if r >= range_threshold:
            ratio = range_threshold / r
            px = sensor[0] + ratio * (px - sensor[0])
            py = sensor[1] + ratio * (py - sensor[1])
        gx = _round((px - offset_x) / resolution)
        gy = _round((py - offset_y) / resolution)
        trace_line(passes, sx, sy, gx, gy)
        if r < range_threshold - 1e-6 and 0 <= gx < width and 0 <= gy < height:
            passes[gy, gx] += 1
            hits[gy, gx] += 1


def grid_dimensions(scans, resolution: float):
    """OccupancyGrid::ComputeDimensions: (width, height, offset (x, y) m) of the bounding box
    of the scans' sensor positions and in-range points."""
    low = np.min([s.box_min for s in scans], axis=0)
    high = np.max([s.box_max for s in scans], axis=0)
    width, height = (int(math.floor(v / resolution + 0.5)) for v in high - low)
    return width, height, low


def counts_from_scans(scans, resolution: float):
    """(passes, hits, offset) of the scans at their corrected poses (CreateFromScans)."""
    width, height, offset = grid_dimensions(scans, resolution)
    passes = np.zeros((height, width), np.int64)
    hits = np.zeros((height, width), np.int64)
    for scan in scans:
        laser = scan.laser
        add_scan(passes, hits, offset[0], offset[1], resolution, scan.sensor_pose, scan.points,
                 scan.ranges, laser.minimum_range, laser.maximum_range, laser.range_threshold)
    return passes, hits, offset


def cell_states(passes, hits, min_pass_through: int, occupancy_threshold: float) -> np.ndarray:
    """OccupancyGrid::UpdateCell on every cell: int8 −1 unknown, 0 free, 100 occupied."""
    data = np.full(passes.shape, UNKNOWN, np.int8)
    seen = passes > min_pass_through
    ratio = np.divide(hits, passes, out=np.zeros(passes.shape), where=passes > 0)
    data[seen] = FREE
    data[seen & (ratio > occupancy_threshold)] = OCCUPIED
    return data

