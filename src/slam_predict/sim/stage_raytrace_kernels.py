"""Numba kernels re-implementing Stage 4.1.1's laser: its cell grid and its ray walk.

Behaviour read from Stage v4.1.1 (libstage/stage.cc, blockgroup.cc, block.cc, world.cc,
region.hh, model_ranger.cc); the code here is written from that description.

- **Bitmap → rectangles** (:func:`cut_rects`, Stage's ``rotrects_from_image_file``): pixels
  whose first channel is ≤ 127 are dark (obstacles). Scanning rows top to bottom and columns left
  to right, each dark pixel not yet used starts a rectangle: it grows right along the dark run,
  its height is the smallest downward dark depth over the run, where the depth search stops at
  the last image row without counting it (so a run touching the bottom row leaves that row out,
  and a run *on* the bottom row gets height 0). The used pixels are whitened. A rectangle is
  stored y-up as x = start column, y = rows − 1 − (start row + height), in pixel units: the
  image's pixels span y ∈ [0, rows − 1], i.e. the picture is one pixel short vertically.
- **Scaling** (``Block::BlockPointToModelMeters``): the bounding box of all rectangle corners is
  stretched to the model's ``size`` and centred on the model's pose.
- **Rasterisation** (``World::MapPoly``): each block's corners go to cells by ``floor(x·ppm)``
  (ppm = 1/resolution) and only the polygon's *outline* is drawn, edge by edge, with an integer
  line walk that marks ``|dx| + |dy|`` cells from each edge's start (its end is the next edge's
  start). Cells group into regions of 32 × 32; a region holding any block (the robot's body
  included) is "populated".
- **Ray walk** (``World::Raytrace``): from (x·ppm, y·ppm) a 4-connected walk whose x/y choice
  follows an error term started from the integer parts of the ray's cell extent
  (``ax = int(|dx|)``), ``ax + ay`` steps in all; the cell of a point is found by truncating
  toward zero (so cell 0 is two cells wide and negative coordinates read one cell lower than
  where the blocks were floored to). Unpopulated regions are jumped over to the next region
  crossing (the walk then resumes from that non-integer point with its old error term). On a
  hit the range is |Δx/cos a| (|Δy/sin a| when the ray is steeper than 45°) from the start to
  the walk's current (not the cell's) coordinate; without a hit it is the ranger's range max.
  The robot's own blocks never count as hits (``ranger_match``) but do populate their regions.
- **Beams** (``ModelRanger::Sensor::Update``): the first ray at −fov/2, each next one
  ``fov/(samples − 1)`` further by repeated addition; ranges are doubles, published as float32.
"""
from __future__ import annotations

import math

import numba
import numpy as np

RBITS = 5
REGION_WIDTH = 1 << RBITS  # cells per region side


@numba.njit(cache=True, nogil=True)
def cut_rects(dark):
    """Stage's rectangle cutter on a bool image (rows, cols; row 0 on top; True = dark).

    Returns int64 (k, 4): x, y, width, height in pixel units, y up (see the module docstring).
    """
    img = dark.copy()
    rows, cols = img.shape
    out = np.empty((64, 4), dtype=np.int64)
    k = 0
    for y in range(rows):
        x = 0
        while x < cols:
            if not img[y, x]:
                x += 1
                continue
            startx = x
            rheight = rows
            while x < cols and img[y, x]:
                yy = y
                while img[yy, x] and yy < rows - 1:
                    yy += 1
                rheight = min(rheight, yy - y)
                x += 1
            img[y:y + rheight, startx:x] = False
            if k == out.shape[0]:
                grown = np.empty((2 * k, 4), dtype=np.int64)
                grown[:k] = out
                out = grown
            out[k, 0] = startx
            out[k, 1] = rows - 1 - (y + rheight)
            out[k, 2] = x - startx
            out[k, 3] = rheight
            k += 1
            x += 1  # the pixel that ended the run is not dark
    return out[:k].copy()


@numba.njit(cache=True, nogil=True)
def _mark_edge(cells, x0, y0, ax0, ay0, ax1, ay1):
    """Add 1 to each cell of Stage's line walk from (ax0, ay0) to (ax1, ay1), end excluded;
    ``cells`` is indexed [y − y0, x − x0] (cells outside it are dropped)."""
    dx = ax1 - ax0
    dy = ay1 - ay0
    sx = -1 if dx < 0 else 1
    sy = -1 if dy < 0 else 1
    ax = abs(dx)
    ay = abs(dy)
    bx = 2 * ax
    by = 2 * ay
    exy = ay - ax
    n = ax + ay
    gx = ax0
    gy = ay0
    rows, cols = cells.shape
    while n > 0:
        r = gy - y0
        c = gx - x0
        if 0 <= r < rows and 0 <= c < cols:
            cells[r, c] += 1
        if exy < 0:
            gx += sx
            exy += by
        else:
            gy += sy
            exy -= bx
        n -= 1


@numba.njit(cache=True, nogil=True)
def map_polys(cells, x0, y0, polys):
    """Draw the outlines of polygons ``polys`` (int64 (k, m, 2) cell corners) into ``cells``."""
    m = polys.shape[1]
    for p in range(polys.shape[0]):
        for i in range(m):
            j = (i + 1) % m
            _mark_edge(cells, x0, y0, polys[p, i, 0], polys[p, i, 1], polys[p, j, 0],
                       polys[p, j, 1])


@numba.njit(cache=True, nogil=True)
def _c_div(a, b):
    """C integer division (truncates toward zero)."""
    q = abs(a) // abs(b)
    return q if (a >= 0) == (b > 0) else -q


@numba.njit(cache=True, nogil=True)
def _populated(regions, rx0, ry0, rx, ry):
    r = ry - ry0
    c = rx - rx0
    return 0 <= r < regions.shape[0] and 0 <= c < regions.shape[1] and regions[r, c] > 0


@numba.njit(cache=True, nogil=True)
def _blocked(occ, x0, y0, ix, iy):
    r = iy - y0
    c = ix - x0
    return 0 <= r < occ.shape[0] and 0 <= c < occ.shape[1] and occ[r, c]


@numba.njit(cache=True, nogil=True, inline="always")
def _region_jump(crossx, crossy, jumpx, jumpy, jumpdist, n, dist, other_dist):
    """Raytrace's leap over an empty region to its next boundary crossing on one axis (the
    nearer one): returns the new global position (px), the pixels left, that axis' next
    crossing and the distances (this axis, the other) to the next crossings."""
    return crossx, crossy, int(n - dist), crossx + jumpx, crossy + jumpy, jumpdist, \
        other_dist - dist


@numba.njit(cache=True, nogil=True)
def stage_ray(occ, regions, x0, y0, ppm, ox, oy, a, range_max):
    """Range (m, float64) of one Stage ray from world (ox, oy) m at heading ``a`` rad.

    ``occ``: bool cells hit by rays, indexed [iy − y0, ix − x0]; ``regions``: block counts of
    the 32×32-cell regions, indexed [ry − y0/32, rx − x0/32] (x0, y0 multiples of 32).
    """
    rx0 = x0 >> RBITS
    ry0 = y0 >> RBITS
    globx = ox * ppm
    globy = oy * ppm
    startx = globx
    starty = globy
    angle = 1e-12 if a == 0.0 else a
    sina = math.sin(angle)
    cosa = math.cos(angle)
    tana = sina / cosa
    dx = ppm * range_max * cosa
    dy = ppm * range_max * sina
    sx = -1 if dx < 0 else 1
    sy = -1 if dy < 0 else 1
    ax = int(abs(dx))
    ay = int(abs(dy))
    bx = 2 * ax
    by = 2 * ay
    exy = ay - ax
    n = ax + ay
    xjumpx = float(sx * REGION_WIDTH)
    xjumpy = (sx * REGION_WIDTH) * tana
    yjumpx = (sy * REGION_WIDTH) / tana
    yjumpy = float(sy * REGION_WIDTH)
    xjumpdist = abs(xjumpx) + abs(xjumpy)
    yjumpdist = abs(yjumpx) + abs(yjumpy)
    xcrossx = xcrossy = ycrossx = ycrossy = 0.0
    dist_x = dist_y = 0.0
    recalc = True
    while n > 0:
        ix = int(globx)
        iy = int(globy)
        if _populated(regions, rx0, ry0, ix >> RBITS, iy >> RBITS):
            recalc = True
            cx = ix & (REGION_WIDTH - 1)
            cy = iy & (REGION_WIDTH - 1)
            while 0 <= cx < REGION_WIDTH and 0 <= cy < REGION_WIDTH and n > 0:
                if _blocked(occ, x0, y0, ix, iy):
                    if ax > ay:
                        return abs((globx - startx) / cosa) / ppm
                    return abs((globy - starty) / sina) / ppm
                if exy < 0:
                    globx += sx
                    exy += by
                    cx += sx
                    ix += sx
                else:
                    globy += sy
                    exy -= bx
                    cy += sy
                    iy += sy
                n -= 1
            continue
        if recalc:
            recalc = False
            regionx = float(_c_div(ix, REGION_WIDTH) * REGION_WIDTH)
            regiony = float(_c_div(iy, REGION_WIDTH) * REGION_WIDTH)
            if globx < 0 and ix - _c_div(ix, REGION_WIDTH) * REGION_WIDTH != 0:
                regionx -= REGION_WIDTH
            if globy < 0 and iy - _c_div(iy, REGION_WIDTH) * REGION_WIDTH != 0:
                regiony -= REGION_WIDTH
            xdx = regionx - globx - 1.0 if sx < 0 else regionx + REGION_WIDTH - globx
            xdy = xdx * tana
            ydy = regiony - globy - 1.0 if sy < 0 else regiony + REGION_WIDTH - globy
            ydx = ydy / tana
            xcrossx = globx + xdx
            xcrossy = globy + xdy
            ycrossx = globx + ydx
            ycrossy = globy + ydy
            dist_x = abs(xdx) + abs(xdy)
            dist_y = abs(ydx) + abs(ydy)
        if dist_x < dist_y:
            globx, globy, n, xcrossx, xcrossy, dist_x, dist_y = _region_jump(
                xcrossx, xcrossy, xjumpx, xjumpy, xjumpdist, n, dist_x, dist_y)
        else:
            globx, globy, n, ycrossx, ycrossy, dist_y, dist_x = _region_jump(
                ycrossx, ycrossy, yjumpx, yjumpy, yjumpdist, n, dist_y, dist_x)
    return range_max


@numba.njit(cache=True, nogil=True)
def stage_scan(occ, regions, x0, y0, ppm, ox, oy, a0, step, range_max, out):
    """Ranges (float32, m) into ``out`` of rays at a0, a0 + step, … (repeated addition, as
    Stage turns its ray) from world (ox, oy); see :func:`stage_ray`."""
    a = a0
    for i in range(out.shape[0]):
        out[i] = stage_ray(occ, regions, x0, y0, ppm, ox, oy, a, range_max)
        a += step
    return out


@numba.njit(cache=True, nogil=True)
def region_counts(cells, x0, y0):
    """Blocks per 32×32 region of ``cells`` (whose shape and origin are multiples of 32)."""
    rows, cols = cells.shape
    out = np.zeros((rows >> RBITS, cols >> RBITS), dtype=np.int64)
    for r in range(rows):
        for c in range(cols):
            if cells[r, c]:
                out[r >> RBITS, c >> RBITS] += cells[r, c]
    return out
