"""numba kernels on bitmaps: generalised Voronoi diagram from a feature transform, and thinning.

Pixels are (row, col); neighbourhood bit i stands for neighbour P(i+2) of the usual thinning
notation, clockwise from north (P2 = north, P3 = north-east, ..., P9 = north-west).
"""
from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True)
def gvd_mask(interior, site_r, site_c, min_sep2):
    """Pixels of the generalised Voronoi diagram of the obstacles, from a feature transform.

    ``site_r/site_c`` give each pixel's nearest obstacle pixel. Two 8-adjacent interior pixels
    whose nearest obstacle pixels are at least sqrt(``min_sep2``) px apart straddle a Voronoi
    edge between two distinct obstacle sites: both are marked. Sites closer than that (the
    same wall, or a wall bump) make no edge, which prunes spurs from wall noise.
    """
    rows, cols = interior.shape
    out = np.zeros((rows, cols), dtype=np.bool_)
    for r in range(rows):
        for c in range(cols):
            if not interior[r, c]:
                continue
            for k in range(4):
                rr = r + (0, 1, 1, 1)[k]
                cc = c + (1, -1, 0, 1)[k]
                if rr >= rows or cc < 0 or cc >= cols or not interior[rr, cc]:
                    continue
                dr = site_r[r, c] - site_r[rr, cc]
                dc = site_c[r, c] - site_c[rr, cc]
                if dr * dr + dc * dc >= min_sep2:
                    out[r, c] = True
                    out[rr, cc] = True
    return out


@numba.njit(cache=True)
def sites_from_labels(labels, is_site):
    """Per-pixel (row, col) of the site pixel whose label it carries (int32 arrays)."""
    rows, cols = labels.shape
    n = 0
    for r in range(rows):
        for c in range(cols):
            n = max(n, labels[r, c])
    tr = np.zeros(n + 1, dtype=np.int32)
    tc = np.zeros(n + 1, dtype=np.int32)
    for r in range(rows):
        for c in range(cols):
            if is_site[r, c]:
                tr[labels[r, c]] = r
                tc[labels[r, c]] = c
    out_r = np.empty((rows, cols), dtype=np.int32)
    out_c = np.empty((rows, cols), dtype=np.int32)
    for r in range(rows):
        for c in range(cols):
            out_r[r, c] = tr[labels[r, c]]
            out_c[r, c] = tc[labels[r, c]]
    return out_r, out_c


def guo_hall_table() -> np.ndarray:
    """Deletion rule of Guo & Hall's (1989) parallel thinning, per sub-iteration and per
    8-neighbourhood (bit i = neighbour P(i+2), clockwise from north)."""
    table = np.zeros((2, 256), dtype=np.bool_)
    for bits in range(256):
        p2, p3, p4, p5, p6, p7, p8, p9 = [(bits >> i) & 1 for i in range(8)]
        crossing = ((not p2) and (p3 or p4)) + ((not p4) and (p5 or p6)) \
            + ((not p6) and (p7 or p8)) + ((not p8) and (p9 or p2))
        n1 = (p9 or p2) + (p3 or p4) + (p5 or p6) + (p7 or p8)
        n2 = (p2 or p3) + (p4 or p5) + (p6 or p7) + (p8 or p9)
        if crossing != 1 or not 2 <= min(n1, n2) <= 3:
            continue
        table[0, bits] = not ((p6 or p7 or not p9) and p8)
        table[1, bits] = not ((p2 or p3 or not p5) and p4)
    return table


_GH_TABLE = guo_hall_table()
_DR8 = np.array([-1, -1, 0, 1, 1, 1, 0, -1], dtype=np.int64)
_DC8 = np.array([0, 1, 1, 1, 0, -1, -1, -1], dtype=np.int64)


@numba.njit(cache=True)
def neighbour_bits(img, r, c) -> int:
    """8-neighbourhood of (r, c) as bits (bit i = P(i+2), clockwise from north; outside = 0)."""
    rows, cols = img.shape
    bits = 0
    for i in range(8):
        rr = r + _DR8[i]
        cc = c + _DC8[i]
        if 0 <= rr < rows and 0 <= cc < cols and img[rr, cc]:
            bits |= 1 << i
    return bits


@numba.njit(cache=True)
def thin(mask, table):
    """Parallel two-sub-iteration thinning of a bool image with a deletion ``table`` (2, 256).

    Each sub-iteration decides on the state at its start; only foreground pixels are
    visited, so the cost is passes × foreground. Stops when a pass deletes nothing.
    """
    img = mask.copy()
    fr, fc = np.nonzero(img)
    count = fr.shape[0]
    delete = np.zeros(count, dtype=np.bool_)
    changed = True
    while changed:
        changed = False
        for sub in range(2):
            for k in range(count):
                delete[k] = table[sub, neighbour_bits(img, fr[k], fc[k])]
            kept = 0
            for k in range(count):
                if delete[k]:
                    img[fr[k], fc[k]] = False
                    changed = True
                else:
                    fr[kept] = fr[k]
                    fc[kept] = fc[k]
                    kept += 1
            count = kept
    return img


def thin_guo_hall(mask: np.ndarray) -> np.ndarray:
    """Guo–Hall thinning of a bool image to 8-connected lines one pixel wide."""
    return thin(np.ascontiguousarray(mask, dtype=np.bool_), _GH_TABLE)


def warmup() -> None:
    """Compile the kernels on a tiny bitmap."""
    free = np.ones((5, 5), dtype=np.bool_)
    free[0], free[-1] = False, False
    site_r, site_c = sites_from_labels(np.ones((5, 5), np.int32), ~free)
    gvd_mask(free, site_r, site_c, 4.0)
    thin_guo_hall(free)
