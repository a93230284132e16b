"""numba kernels of the GMapping port: scan score/likelihood, hill-climbing, hit registration.

Particle maps (see :mod:`.maps`) are a per-particle int32 ``table`` of patch ids (-1 = not
allocated) into a shared pool of 32 x 32-cell patches: ``acc`` float32 (P, 1024, 2) sums of hit
points (m) and ``hits`` int32 (P, 1024) hit counts. Particle maps only ever receive endpoint hits
(openslam_gmapping's ``generateMap=false``), so a cell's occupancy n/visits is 1.0 when it has
hits and "unknown" (−1) otherwise. Cell (ix, iy) lives in patch (ix >> 5, iy >> 5) at slot
(ix & 31) * 32 + (iy & 31). world → cell is C's ``round((p − centre)/delta) + size/2``.

Geometry arguments ``sx2, sy2, cx, cy, delta`` are the map's cell index of its centre, the centre
(m) and the cell size (m). Poses are laser poses (x m, y m, θ rad); ``ca, sa`` are cos/sin of the
beam angles in the laser frame. The matcher's own laser offset is always zero, as in slam_gmapping.
"""
from __future__ import annotations

import math

import numba as nb
import numpy as np

from slam_predict.slam.gmapping.params import FREE_CELL_RATIO, NULL_LIKELIHOOD

PATCH_BITS = 5
PATCH_MASK = 31
PATCH_CELLS = 1024


@nb.njit(cache=True, inline="always")
def c_round(v):
    """C's round(): halves away from zero (numpy rounds halves to even)."""
    if v >= 0.0:
        return int(math.floor(v + 0.5))
    return -int(math.floor(-v + 0.5))


@nb.njit(cache=True, inline="always")
def patch_id(table, ix, iy):
    """Pool index of the patch holding cell (ix, iy), or -1 (outside or not allocated)."""
    if ix < 0 or iy < 0:
        return -1
    px = ix >> PATCH_BITS
    py = iy >> PATCH_BITS
    if px >= table.shape[0] or py >= table.shape[1]:
        return -1
    return table[px, py]


@nb.njit(cache=True, inline="always")
def slot(ix, iy):
    """Index of cell (ix, iy) inside its patch."""
    return ((ix & PATCH_MASK) << PATCH_BITS) | (iy & PATCH_MASK)


@nb.njit(cache=True, inline="always")
def _is_hit(table, hits, ix, iy):
    pid = patch_id(table, ix, iy)
    return pid >= 0 and hits[pid, slot(ix, iy)] > 0


@nb.njit(cache=True, inline="always")
def _window_walk(table, acc, hits, x0, y0, width, ofx, ofy, means, one_pid):
    """The window walk of :func:`_window_means`; ``one_pid`` ≥ 0 is the patch of every
    cell of the window, -1 looks each cell's patch up."""
    k = 0
    pid = one_pid
    for xx in range(width):
        px = x0 + xx
        for yy in range(width):
            py = y0 + yy
            if one_pid < 0:
                pid = patch_id(table, px, py)
                if pid < 0:
                    continue
            s = slot(px, py)
            n = hits[pid, s]
            if n <= 0:
                continue
            if _is_hit(table, hits, px + ofx, py + ofy):
                continue
            inv = 1.0 / n
            means[k, 0] = inv * np.float64(acc[pid, s, 0])
            means[k, 1] = inv * np.float64(acc[pid, s, 1])
            k += 1
    return k


@nb.njit(cache=True, inline="always")
def _window_means(table, acc, hits, ix, iy, ofx, ofy, ksize, means):
    """The means (m) of the matching cells of the (2k+1)² window around (ix, iy) into
    ``means`` (k, 2), window order; returns k. A cell matches when it is occupied and its
    companion cell, offset by (ofx, ofy) cells, is not. A window inside one patch (most of
    them) looks its patch up once."""
    x0 = ix - ksize
    y0 = iy - ksize
    width = 2 * ksize + 1
    if (x0 >= 0 and y0 >= 0 and (x0 >> PATCH_BITS) == ((ix + ksize) >> PATCH_BITS)
            and (y0 >> PATCH_BITS) == ((iy + ksize) >> PATCH_BITS)):
        pid = patch_id(table, x0, y0)
        if pid < 0:
            return 0
        return _window_walk(table, acc, hits, x0, y0, width, ofx, ofy, means, pid)
    return _window_walk(table, acc, hits, x0, y0, width, ofx, ofy, means, -1)


@nb.njit(cache=True, inline="always")
def _nearest_d2(hx, hy, means, k):
    """Squared distance (m²) from (hx, hy) to the nearest of the first ``k`` means, -1 if
    k = 0."""
    if k == 0:
        return -1.0
    best = np.inf
    for j in range(k):
        mx = hx - means[j, 0]
        my = hy - means[j, 1]
        d2 = mx * mx + my * my
        if d2 < best:
            best = d2
    return best


@nb.njit(cache=True)
def _best_d2(table, acc, hits, hx, hy, ix, iy, ofx, ofy, ksize):
    """Squared distance (m²) from the hit to the nearest matching cell mean of the window
    around (ix, iy), -1 if none matches (:func:`_window_means`)."""
    means = np.empty(((2 * ksize + 1) ** 2, 2))
    k = _window_means(table, acc, hits, ix, iy, ofx, ofy, ksize, means)
    return _nearest_d2(hx, hy, means, k)


@nb.njit(cache=True, inline="always")
def _free_offset(x, y, r, dx, dy, hx, hy, ix, iy, sx2, sy2, cx, cy, delta, back, bug):
    """Cell offset of the companion "free" cell of a hit (upstream bug or intended rule)."""
    if bug:
        # upstream: world2map of a *relative* vector -> lands about half a map away
        fx = (x + (r - back) * dx) - hx
        fy = (y + (r - back) * dy) - hy
        return c_round((fx - cx) / delta) + sx2, c_round((fy - cy) / delta) + sy2
    fx = hx - back * dx
    fy = hy - back * dy
    return c_round((fx - cx) / delta) + sx2 - ix, c_round((fy - cy) / delta) + sy2 - iy


@nb.njit(cache=True, inline="always")
def _beam_hit(x, y, c, s, r, cai, sai, sx2, sy2, cx, cy, delta, back, bug):
    """A beam of range ``r`` from laser pose (x, y) heading θ (c, s = cos θ, sin θ; cai, sai
    = cos, sin of the beam angle): hit point (m), its cell and the companion offset."""
    dx = c * cai - s * sai
    dy = s * cai + c * sai
    hx = x + r * dx
    hy = y + r * dy
    ix = c_round((hx - cx) / delta) + sx2
    iy = c_round((hy - cy) / delta) + sy2
    ofx, ofy = _free_offset(x, y, r, dx, dy, hx, hy, ix, iy, sx2, sy2, cx, cy, delta, back, bug)
    return hx, hy, ix, iy, ofx, ofy


@nb.njit(cache=True)
def score(table, sx2, sy2, cx, cy, delta, acc, hits, x, y, th, ranges, ca, sa,
          usable, sigma, ksize, lskip, bug):
    """ScanMatcher::score: Σ exp(−d²/sigma) over used beams with 0 < r ≤ usable (each beam's
    best squared distance to a matching cell mean of its window, :func:`_best_d2`).
    :func:`score_cached` with a new cache."""
    keys, means, counts = new_score_cache(ranges.shape[0], ksize)
    return score_cached(table, sx2, sy2, cx, cy, delta, acc, hits, x, y, th, ranges, ca, sa,
                        usable, sigma, ksize, lskip, bug, keys, means, counts)


@nb.njit(cache=True)
def new_score_cache(beams, ksize):
    """An empty cache of :func:`score_cached` for ``beams`` beams: (keys, means, counts)."""
    width = 2 * ksize + 1
    keys = np.full((beams, 4), -(1 << 62), np.int64)
    return keys, np.empty((beams, width * width, 2)), np.zeros(beams, np.int64)


@nb.njit(cache=True)
def score_cached(table, sx2, sy2, cx, cy, delta, acc, hits, x, y, th, ranges, ca, sa,
                 usable, sigma, ksize, lskip, bug, keys, means, counts):
    """:func:`score`, keeping per beam the means of its window's matching cells: a beam
    whose hit cell and companion offset are those it had at the last call with the same
    arrays reuses them instead of looking the window up again (the same numbers, so the same
    score). ``keys`` (B, 4) int64 (hit cell, companion offset; start with a value no cell
    has), ``means`` (B, (2k+1)², 2) float64 and ``counts`` (B,) int64 are the cache of one
    map; B = the number of beams."""
    c = math.cos(th)
    s = math.sin(th)
    # upstream's score() steps back r − delta·freeDelta = r − delta²·√2 (bug); intended: δ·√2
    back = delta * delta * FREE_CELL_RATIO if bug else delta * FREE_CELL_RATIO
    total = 0.0
    skip = 0
    for i in range(ranges.shape[0]):
        skip += 1
        if skip > lskip:
            skip = 0
        r = ranges[i]
        if skip != 0 or r > usable or r == 0.0:
            continue
        hx, hy, ix, iy, ofx, ofy = _beam_hit(x, y, c, s, r, ca[i], sa[i], sx2, sy2, cx, cy,
                                             delta, back, bug)
        if not (keys[i, 0] == ix and keys[i, 1] == iy and keys[i, 2] == ofx
                and keys[i, 3] == ofy):
            keys[i, 0] = ix
            keys[i, 1] = iy
            keys[i, 2] = ofx
            keys[i, 3] = ofy
            counts[i] = _window_means(table, acc, hits, ix, iy, ofx, ofy, ksize, means[i])
        k = counts[i]
        if k == 0:
            continue
        best = np.inf      # _nearest_d2 of means[i], without a view a beam
        for j in range(k):
            mx = hx - means[i, j, 0]
            my = hy - means[i, j, 1]
            d2 = mx * mx + my * my
            if d2 < best:
                best = d2
        total += math.exp(-best / sigma)
    return total


@nb.njit(cache=True)
def likelihood_and_score(table, sx2, sy2, cx, cy, delta, acc, hits, x, y, th, ranges, ca, sa,
                         usable, sigma, lsigma, ksize, lskip, bug):
    """ScanMatcher::likelihoodAndScore → (score, log-likelihood, matched beams).

    Beams with r ≤ usable count (r = 0 included, as upstream): −d²/lsigma when matched, else
    nullLikelihood/lsigma.
    """
    c = math.cos(th)
    s = math.sin(th)
    back = delta * FREE_CELL_RATIO
    no_hit = NULL_LIKELIHOOD / lsigma
    total_s = 0.0
    total_l = 0.0
    matched = 0
    skip = 0
    means = np.empty(((2 * ksize + 1) ** 2, 2))
    for i in range(ranges.shape[0]):
        skip += 1
        if skip > lskip:
            skip = 0
        r = ranges[i]
        if r > usable or skip != 0:
            continue
        hx, hy, ix, iy, ofx, ofy = _beam_hit(x, y, c, s, r, ca[i], sa[i], sx2, sy2, cx, cy,
                                             delta, back, bug)
        k = _window_means(table, acc, hits, ix, iy, ofx, ofy, ksize, means)
        d2 = _nearest_d2(hx, hy, means, k)
        if d2 >= 0.0:
            total_s += math.exp(-d2 / sigma)
            total_l += -d2 / lsigma
            matched += 1
        else:
            total_l += no_hit
    return total_s, total_l, matched


@nb.njit(cache=True)
def optimize(table, sx2, sy2, cx, cy, delta, acc, hits, x0, y0, th0, ranges, ca, sa,
             usable, sigma, ksize, lskip, bug, lstep, astep, iterations):
    """ScanMatcher::optimize hill climbing → (x, y, θ, best score).

    Each round tries x±l, y±l (map axes) and θ±a from the current pose and moves to the best
    strictly better one. A round without improvement halves l and a (refinement + 1); the search
    stops after a non-improving round once refinements ≥ iterations. The score of the pose
    left by the last move is remembered: the move straight back, when it lands on exactly that
    pose, is not scored again (same result, one score fewer). The scores share one cache of
    window lookups (:func:`score_cached`).
    """
    best_score = -1.0
    px, py, pth = x0, y0, th0
    keys, means, counts = new_score_cache(ranges.shape[0], ksize)
    current = score_cached(table, sx2, sy2, cx, cy, delta, acc, hits, px, py, pth, ranges, ca,
                           sa, usable, sigma, ksize, lskip, bug, keys, means, counts)
    adelta = astep
    ldelta = lstep
    refinement = 0
    qx = qy = qth = math.nan  # the pose left by the last move (NaN: none yet) and its score
    qscore = 0.0
    while True:
        if best_score >= current:
            refinement += 1
            adelta *= 0.5
            ldelta *= 0.5
        best_score = current
        bx, by, bth = px, py, pth
        moved = False
        for move in range(6):
            lx, ly, lth = px, py, pth
            if move == 0:
                lx += ldelta
            elif move == 1:
                lx -= ldelta
            elif move == 2:
                ly -= ldelta
            elif move == 3:
                ly += ldelta
            elif move == 4:
                lth += adelta
            else:
                lth -= adelta
            if lx == qx and ly == qy and lth == qth:
                local = qscore
            else:
                local = score_cached(table, sx2, sy2, cx, cy, delta, acc, hits, lx, ly, lth,
                                     ranges, ca, sa, usable, sigma, ksize, lskip, bug, keys,
                                     means, counts)
            if local > current:
                current = local
                bx, by, bth = lx, ly, lth
                moved = True
        if moved:
            qx, qy, qth, qscore = px, py, pth, best_score
        px, py, pth = bx, by, bth
        if not (current > best_score or refinement < iterations):
            break
    return px, py, pth, best_score


@nb.njit(cache=True)
def match_particle(table, sx2, sy2, cx, cy, delta, acc, hits, x0, y0, th0, ranges, ca, sa,
                   usable, sigma, lsigma, ksize, lskip, bug, lstep, astep, iterations,
                   minimum_score):
    """GridSlamProcessor::scanMatch for one particle → (x, y, θ, score, log-likelihood).

    The optimum replaces the sampled pose only when its score exceeds ``minimum_score``.
    """
    ox, oy, oth, best = optimize(table, sx2, sy2, cx, cy, delta, acc, hits, x0, y0, th0,
                                 ranges, ca, sa, usable, sigma, ksize, lskip, bug, lstep, astep,
                                 iterations)
    if best > minimum_score:
        x, y, th = ox, oy, oth
    else:
        x, y, th = x0, y0, th0
    _, lik, _ = likelihood_and_score(table, sx2, sy2, cx, cy, delta, acc, hits, x, y, th,
                                     ranges, ca, sa, usable, sigma, lsigma, ksize, lskip, bug)
    return x, y, th, best, lik


@nb.njit(cache=True)
def scan_bounds(x, y, th, ranges, ca, sa, max_range, usable):
    """(xmin, ymin, xmax, ymax) m of the laser position and the beams with 0 < r ≤ max_range,
    each cropped to ``usable`` (computeActiveArea's extent test)."""
    c = math.cos(th)
    s = math.sin(th)
    x0 = x1 = x
    y0 = y1 = y
    for i in range(ranges.shape[0]):
        r = ranges[i]
        if r > max_range or r == 0.0:
            continue
        if r > usable:
            r = usable
        hx = x + r * (c * ca[i] - s * sa[i])
        hy = y + r * (s * ca[i] + c * sa[i])
        x0 = min(x0, hx)
        x1 = max(x1, hx)
        y0 = min(y0, hy)
        y1 = max(y1, hy)
    return x0, y0, x1, y1


@nb.njit(cache=True)
def scans_bounds(poses, readings, ca, sa, max_range, usable):
    """:func:`scan_bounds` of every scan: (K, 4) rows (xmin, ymin, xmax, ymax) m."""
    out = np.empty((poses.shape[0], 4))
    for k in range(poses.shape[0]):
        x0, y0, x1, y1 = scan_bounds(poses[k, 0], poses[k, 1], poses[k, 2], readings[k], ca, sa,
                                     max_range, usable)
        out[k, 0] = x0
        out[k, 1] = y0
        out[k, 2] = x1
        out[k, 3] = y1
    return out


@nb.njit(cache=True, inline="always")
def _inside(x, y, cx, cy, delta, sx2, sy2, nx, ny):
    ix = c_round((x - cx) / delta) + sx2
    iy = c_round((y - cy) / delta) + sy2
    return ix >= 0 and iy >= 0 and (ix >> PATCH_BITS) < nx and (iy >> PATCH_BITS) < ny


@nb.njit(cache=True)
def first_outside(bounds, start, cx, cy, delta, sx2, sy2, nx, ny):
    """Index of the first row of ``bounds`` (K, 4) from ``start`` on that makes
    ``Geometry.grow_to`` resize the map of geometry (cx, cy, delta, sx2, sy2, nx, ny), or −1."""
    lxmin = (0 - sx2) * delta + cx
    lymin = (0 - sy2) * delta + cy
    lxmax = ((nx << PATCH_BITS) - 1 - sx2) * delta + cx
    lymax = ((ny << PATCH_BITS) - 1 - sy2) * delta + cy
    for k in range(start, bounds.shape[0]):
        xmin = min(bounds[k, 0], lxmin)
        ymin = min(bounds[k, 1], lymin)
        xmax = max(bounds[k, 2], lxmax)
        ymax = max(bounds[k, 3], lymax)
        if not (_inside(xmin, ymin, cx, cy, delta, sx2, sy2, nx, ny)
                and _inside(xmax, ymax, cx, cy, delta, sx2, sy2, nx, ny)):
            return k
    return -1


@nb.njit(cache=True)
def _hit_cells(x, y, th, ranges, ca, sa, max_range, usable, sx2, sy2, cx, cy, delta):
    """Hit points (m) and cells of the beams a particle map registers (0 < r ≤ both limits)."""
    n = ranges.shape[0]
    pts = np.empty((n, 2))
    cells = np.empty((n, 2), dtype=np.int64)
    c = math.cos(th)
    s = math.sin(th)
    k = 0
    for i in range(n):
        r = ranges[i]
        if r > max_range or r > usable or r == 0.0:
            continue
        hx = x + r * (c * ca[i] - s * sa[i])
        hy = y + r * (s * ca[i] + c * sa[i])
        pts[k, 0] = hx
        pts[k, 1] = hy
        cells[k, 0] = c_round((hx - cx) / delta) + sx2
        cells[k, 1] = c_round((hy - cy) / delta) + sy2
        k += 1
    return pts[:k], cells[:k]


@nb.njit(cache=True)
def register_hits(table, sx2, sy2, cx, cy, delta, acc, hits, ref, free_stack, free_top,
                  x, y, th, ranges, ca, sa, max_range, usable):
    """ScanMatcher::registerScan with generateMap=false, copy-on-write per patch.

    Every patch receiving a hit is made private first: an unallocated one is taken zeroed from
    the pool, a shared one (ref > 1) is copied. Returns the number of patches taken from the
    pool, or −(number needed) without touching anything when the pool has too few free patches
    (grow it and call again). Hits outside the table (cannot happen after the growth test) are
    dropped; the count of dropped hits is not reported.
    """
    pts, cells = _hit_cells(x, y, th, ranges, ca, sa, max_range, usable, sx2, sy2, cx, cy, delta)
    nx, ny = table.shape[0], table.shape[1]
    keys = np.empty(cells.shape[0], dtype=np.int64)
    m = 0
    for k in range(cells.shape[0]):
        ix, iy = cells[k, 0], cells[k, 1]
        if ix < 0 or iy < 0 or (ix >> PATCH_BITS) >= nx or (iy >> PATCH_BITS) >= ny:
            continue
        keys[m] = (ix >> PATCH_BITS) * ny + (iy >> PATCH_BITS)
        m += 1
    active = np.unique(keys[:m])
    need = 0
    for key in active:
        pid = table[key // ny, key % ny]
        if pid < 0 or ref[pid] > 1:
            need += 1
    if need > free_top[0]:
        return -need
    for key in active:
        px, py = key // ny, key % ny
        pid = table[px, py]
        if pid >= 0 and ref[pid] == 1:
            continue
        free_top[0] -= 1
        new = free_stack[free_top[0]]
        if pid < 0:
            acc[new] = 0.0
            hits[new] = 0
        else:
            acc[new] = acc[pid]
            hits[new] = hits[pid]
            ref[pid] -= 1
        ref[new] = 1
        table[px, py] = new
    for k in range(cells.shape[0]):
        ix, iy = cells[k, 0], cells[k, 1]
        pid = patch_id(table, ix, iy)
        if pid < 0:
            continue
        sl = slot(ix, iy)
        acc[pid, sl, 0] += np.float32(pts[k, 0])
        acc[pid, sl, 1] += np.float32(pts[k, 1])
        hits[pid, sl] += 1
    return need


@nb.njit(cache=True)
def retain_table(table, ref):
    """One more map refers to every patch of ``table``."""
    for px in range(table.shape[0]):
        for py in range(table.shape[1]):
            pid = table[px, py]
            if pid >= 0:
                ref[pid] += 1


@nb.njit(cache=True)
def release_table(table, ref, free_stack, free_top):
    """A map referring to ``table`` is dropped: patches nobody refers to return to the pool."""
    for px in range(table.shape[0]):
        for py in range(table.shape[1]):
            pid = table[px, py]
            if pid >= 0:
                ref[pid] -= 1
                if ref[pid] == 0:
                    free_stack[free_top[0]] = pid
                    free_top[0] += 1


def warmup() -> None:
    """Compile (or load from the numba cache) every kernel on a tiny input (raytrace.py's are
    warmed by its own ``warmup``, listed in :data:`slam_predict.warmup.MODULES`)."""
    table = np.full((2, 2), -1, dtype=np.int32)
    acc = np.zeros((4, PATCH_CELLS, 2), dtype=np.float32)
    hits = np.zeros((4, PATCH_CELLS), dtype=np.int32)
    ref = np.zeros(4, dtype=np.int32)
    free_stack = np.arange(4, dtype=np.int32)[::-1].copy()
    free_top = np.array([4], dtype=np.int64)
    ranges = np.array([1.0, 1.2, 0.0, 50.0])
    ang = np.linspace(-1.0, 1.0, 4)
    ca, sa = np.cos(ang), np.sin(ang)
    args = (32, 32, 0.0, 0.0, 0.05)
    register_hits(table, *args, acc, hits, ref, free_stack, free_top, 0.0, 0.0, 0.0, ranges,
                  ca, sa, 10.0, 10.0)
    for bug in (True, False):
        match_particle(table, *args, acc, hits, 0.0, 0.0, 0.0, ranges, ca, sa, 10.0, 0.05, 0.075,
                       1, 0, bug, 0.05, 0.05, 1, 0.0)
    scan_bounds(0.0, 0.0, 0.0, ranges, ca, sa, 10.0, 10.0)
    bounds = scans_bounds(np.zeros((1, 3)), ranges.reshape(1, -1), ca, sa, 10.0, 10.0)
    first_outside(bounds, 0, 0.0, 0.0, 0.05, 32, 32, 2, 2)
    retain_table(table, ref)
    release_table(table, ref, free_stack, free_top)
