"""Slow, literal pure-Python model of Stage 4.1.1's laser, for testing the numba kernels.

Written straight from the behaviour of Stage v4.1.1 (libstage/stage.cc rect cutter,
blockgroup.cc/block.cc scaling, world.cc MapPoly and Raytrace, region.hh bit tricks): plain
loops, superregions/regions/cells held in dicts as Stage holds them in maps and arrays, C integer
conversions spelled out. No numpy in the algorithms.
"""
from __future__ import annotations

import math

RBITS = 5
SBITS = 5
SRBITS = RBITS + SBITS
REGIONWIDTH = 1 << RBITS
CELLMASK = REGIONWIDTH - 1
REGIONMASK = (1 << SRBITS) - 1


def to_int32(v: float) -> int:
    """C's double → int32_t conversion (truncation toward zero)."""
    return int(v)


def getcell(x: int) -> int:
    return x & CELLMASK


def getreg(x: int) -> int:
    return (x & REGIONMASK) >> RBITS


def getsreg(x: int) -> int:
    return x >> SRBITS


def c_div(a: int, b: int) -> int:
    q = abs(a) // abs(b)
    return q if (a >= 0) == (b > 0) else -q


def c_mod(a: int, b: int) -> int:
    return a - c_div(a, b) * b


def sgn(v) -> int:
    return -1 if v < 0 else 1


def line_step(globx, globy, cx, cy, exy, sx, sy, bx, by):
    """One step of Stage's Bresenham walk (map_poly and Raytrace): the global pixel, the cell
    in its region and the error term after it."""
    if exy < 0:
        return globx + sx, globy, cx + sx, cy, exy + by
    return globx, globy + sy, cx, cy + sy, exy - bx


def region_jump(cross, jump, jumpdist, n, dist, other_dist):
    """Raytrace's jump to the next region boundary crossing on one axis: (global x, y, pixels
    left, that axis' next crossing, distances to the next crossings on this and the other
    axis)."""
    return (cross[0], cross[1], to_int32(n - dist), (cross[0] + jump[0], cross[1] + jump[1]),
            jumpdist, other_dist - dist)


def cut_rects(dark: list[list[bool]]) -> list[tuple[int, int, int, int]]:
    """Stage's rotrects_from_image on rows of booleans (row 0 on top, True = dark)."""
    img = [list(row) for row in dark]
    height, width = len(img), len(img[0])

    def is_set(x, y):  # white pixel
        return not img[y][x]

    rects = []
    for y in range(height):
        x = 0
        while x < width:
            if is_set(x, y):
                x += 1
                continue
            startx, starty = x, y
            rheight = height
            while x < width and not is_set(x, y):
                yy = y
                while not is_set(x, yy) and yy < height - 1:
                    yy += 1
                if yy - y < rheight:
                    rheight = yy - y
                x += 1
            for a in range(starty, starty + rheight):
                for b in range(startx, x):
                    img[a][b] = False
            rects.append((startx, height - 1 - (starty + rheight), x - startx, rheight))
            x += 1
    return rects


def block_points(rects, boundary: bool):
    """Each rectangle's 4 points (x, y), (x+w, y), (x+w, y+h), (x, y+h), + boundary strips."""
    blocks = [[(x, y), (x + w, y), (x + w, y + h), (x, y + h)] for x, y, w, h in rects]
    if boundary:
        minx = min(p[0] for b in blocks for p in b)
        miny = min(p[1] for b in blocks for p in b)
        maxx = max(p[0] for b in blocks for p in b)
        maxy = max(p[1] for b in blocks for p in b)
        sx, sy, eps = maxx - minx, maxy - miny, 0.01
        for x, y, w, h in ((minx, miny, eps, sy), (minx, miny, sx, eps),
                           (minx, maxy - eps, sx, eps), (maxx - eps, miny, eps, sy)):
            blocks.append([(x, y), (x + w, y), (x + w, y + h), (x, y + h)])
    return blocks


def global_pixels(blocks, size, pose, ppm):
    """Block points → model metres (bounding box stretched to ``size``) → global cells."""
    minx = min(p[0] for b in blocks for p in b)
    miny = min(p[1] for b in blocks for p in b)
    maxx = max(p[0] for b in blocks for p in b)
    maxy = max(p[1] for b in blocks for p in b)
    bgx, bgy = maxx - minx, maxy - miny
    offx, offy = minx + bgx / 2.0, miny + bgy / 2.0
    out = []
    for b in blocks:
        pts = []
        for bx, by in b:
            mx = (bx - offx) * (size[0] / bgx)
            my = (by - offy) * (size[1] / bgy)
            gx = pose[0] + mx * 1.0 - my * 0.0
            gy = pose[1] + mx * 0.0 + my * 1.0
            pts.append((math.floor(gx * ppm), math.floor(gy * ppm)))
        out.append(pts)
    return out


class Grid:
    """Superregions {(sx, sy): {(rx, ry): region}}, region = {"count": n, "cells": {(cx, cy):
    [models]}}."""

    def __init__(self):
        self.superregions = {}

    def region(self, sreg, reg, create):
        sr = self.superregions.get(sreg)
        if sr is None:
            if not create:
                return None
            sr = self.superregions[sreg] = {}
        r = sr.get(reg)
        if r is None:
            r = sr[reg] = {"count": 0, "cells": {}}
        return r

    def map_poly(self, pts, model):
        """World::MapPoly: the outline, edge by edge, region by region."""
        for i in range(len(pts)):
            start, end = pts[i], pts[(i + 1) % len(pts)]
            dx, dy = end[0] - start[0], end[1] - start[1]
            sx, sy = sgn(dx), sgn(dy)
            ax, ay = abs(dx), abs(dy)
            bx, by = 2 * ax, 2 * ay
            exy, n = ay - ax, ax + ay
            globx, globy = start
            while n:
                reg = self.region((getsreg(globx), getsreg(globy)),
                                  (getreg(globx), getreg(globy)), True)
                cx, cy = getcell(globx), getcell(globy)
                while 0 <= cx < REGIONWIDTH and 0 <= cy < REGIONWIDTH and n > 0:
                    reg["cells"].setdefault((cx, cy), []).append(model)
                    reg["count"] += 1
                    globx, globy, cx, cy, exy = line_step(globx, globy, cx, cy, exy, sx, sy,
                                                          bx, by)
                    n -= 1

    def raytrace(self, ox, oy, a, rng, ppm, ignore=("robot",)):
        """World::Raytrace of one ray; models in ``ignore`` are not hits. Range in m."""
        globx, globy = ox * ppm, oy * ppm
        startx, starty = globx, globy
        angle = 1e-12 if a == 0.0 else a
        sina, cosa = math.sin(angle), math.cos(angle)
        tana = sina / cosa
        dx, dy = ppm * rng * cosa, ppm * rng * sina
        sx, sy = sgn(dx), sgn(dy)
        ax, ay = to_int32(abs(dx)), to_int32(abs(dy))
        bx, by = 2 * ax, 2 * ay
        exy, n = ay - ax, ax + ay
        xjumpx, xjumpy = sx * REGIONWIDTH, sx * REGIONWIDTH * tana
        yjumpx, yjumpy = sy * REGIONWIDTH / tana, sy * REGIONWIDTH
        xjumpdist = abs(xjumpx) + abs(xjumpy)
        yjumpdist = abs(yjumpx) + abs(yjumpy)
        xcrossx = xcrossy = ycrossx = ycrossy = dist_x = dist_y = 0.0
        calculate = True
        while n > 0:
            ix, iy = to_int32(globx), to_int32(globy)
            reg = self.region((getsreg(ix), getsreg(iy)), (getreg(ix), getreg(iy)), False)
            if reg is not None and reg["count"]:
                calculate = True
                cx, cy = getcell(ix), getcell(iy)
                while 0 <= cx < REGIONWIDTH and 0 <= cy < REGIONWIDTH and n > 0:
                    for model in reg["cells"].get((cx, cy), []):
                        if model in ignore:
                            continue
                        if ax > ay:
                            return abs((globx - startx) / cosa) / ppm
                        return abs((globy - starty) / sina) / ppm
                    globx, globy, cx, cy, exy = line_step(globx, globy, cx, cy, exy, sx, sy,
                                                          bx, by)
                    n -= 1
                continue
            if calculate:
                calculate = False
                ix, iy = to_int32(globx), to_int32(globy)
                regionx = float(c_div(ix, REGIONWIDTH) * REGIONWIDTH)
                regiony = float(c_div(iy, REGIONWIDTH) * REGIONWIDTH)
                if globx < 0 and c_mod(ix, REGIONWIDTH):
                    regionx -= REGIONWIDTH
                if globy < 0 and c_mod(iy, REGIONWIDTH):
                    regiony -= REGIONWIDTH
                xdx = regionx - globx - 1.0 if sx < 0 else regionx + REGIONWIDTH - globx
                xdy = xdx * tana
                ydy = regiony - globy - 1.0 if sy < 0 else regiony + REGIONWIDTH - globy
                ydx = ydy / tana
                xcrossx, xcrossy = globx + xdx, globy + xdy
                ycrossx, ycrossy = globx + ydx, globy + ydy
                dist_x = abs(xdx) + abs(xdy)
                dist_y = abs(ydx) + abs(ydy)
            if dist_x < dist_y:
                globx, globy, n, (xcrossx, xcrossy), dist_x, dist_y = region_jump(
                    (xcrossx, xcrossy), (xjumpx, xjumpy), xjumpdist, n, dist_x, dist_y)
            else:
                globx, globy, n, (ycrossx, ycrossy), dist_y, dist_x = region_jump(
                    (ycrossx, ycrossy), (yjumpx, yjumpy), yjumpdist, n, dist_y, dist_x)
        return rng


def robot_body(x, y, yaw, side, ppm):
    """A position model's default block (unit square scaled to side) at (x, y, yaw): cells."""
    c, s = math.cos(yaw), math.sin(yaw)
    pts = []
    for bx, by in ((-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)):
        mx, my = bx * side, by * side
        pts.append((math.floor((x + mx * c - my * s) * ppm),
                    math.floor((y + mx * s + my * c) * ppm)))
    return pts


def stage_grid(dark, size, pose, resolution, boundary=True) -> tuple[Grid, float]:
    """The Grid of a floor plan image ``dark`` (rows of bools) of ``size`` (W, H m) at ``pose``
    (x, y m); returns it with ppm."""
    ppm = 1.0 / resolution
    grid = Grid()
    for pts in global_pixels(block_points(cut_rects(dark), boundary), size, pose, ppm):
        grid.map_poly(pts, "floorplan")
    return grid, ppm


def scan(grid, ppm, laser, fov, samples, rng):
    """ModelRanger::Sensor::Update: ranges of ``samples`` rays from laser (x, y, yaw)."""
    incr = fov / max(samples - 1, 1)
    a = laser[2] + (-fov / 2.0 if samples > 1 else 0.0)
    while a < -math.pi:
        a += 2.0 * math.pi
    while a > math.pi:
        a -= 2.0 * math.pi
    out = []
    for _ in range(samples):
        out.append(grid.raytrace(laser[0], laser[1], a, rng, ppm))
        a += incr
    return out
