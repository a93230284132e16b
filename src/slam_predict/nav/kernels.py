"""numba kernels of the navigation stack: costmap inflation, grid search, ray tracing, BFS.

Grids are indexed ``[my, mx]`` (row = y cell, column = x cell), as costmap_2d's
``index = my * size_x + mx``; the rollout kernels live in :mod:`slam_predict.nav.rollout`.
``warmup()`` compiles everything (listed in :mod:`slam_predict.warmup`).
"""
from __future__ import annotations

import math

import numba
import numpy as np

FREE = 0
INSCRIBED = 253
LETHAL = 254
NO_INFORMATION = 255


# --------------------------------------------------------------------------------------------
# Inflation (costmap_2d InflationLayer::updateCosts)
# --------------------------------------------------------------------------------------------
@numba.njit(cache=True)
def inflate(master, min_i, min_j, max_i, max_j, radius, cost_cache, dist_cache, bin_of, nbins,
            inflate_unknown, cell, src, nxt):
    """Brushfire inflation of LETHAL cells of ``master`` (uint8 [ny, nx]) in place.

    Sources: LETHAL cells within the update window [min_i, max_i) x [min_j, max_j) grown by
    ``radius`` cells. Cells whose cost would be FREE are not queued: cost falls with distance,
    so they and everything beyond them would leave ``master`` unchanged. Cells are processed in
    bins of exact distance to their source (FIFO inside a bin, as costmap_2d's
    ``std::map<double, vector>``; a cell enqueued into an already-passed bin is dropped, as
    there). Costs are only written inside the window:
    ``max(old, cost)``, except that unknown cells take only costs >= INSCRIBED (or > FREE with
    ``inflate_unknown``).

    ``cell``, ``src``, ``nxt`` (int32, same length) are the work pool; returns the number of
    queue entries used, or -1 when the pool was too small (``master`` is then partly
    updated: restore it and retry with a larger pool).
    """
    ny, nx = master.shape
    if radius <= 0:
        return 0
    wi0 = max(0, min_i - radius)
    wj0 = max(0, min_j - radius)
    wi1 = min(nx, max_i + radius)
    wj1 = min(ny, max_j + radius)
    seen = np.zeros(ny * nx, np.bool_)
    cap = cell.shape[0]
    head = np.full(nbins, -1, np.int64)
    tail = np.full(nbins, -1, np.int64)
    n = 0
    for j in range(wj0, wj1):
        for i in range(wi0, wi1):
            if master[j, i] == LETHAL:
                if n >= cap:
                    return -1
                idx = j * nx + i
                cell[n] = idx
                src[n] = idx
                nxt[n] = -1
                if tail[0] == -1:
                    head[0] = n
                else:
                    nxt[tail[0]] = n
                tail[0] = n
                n += 1
    for b in range(nbins):
        node = head[b]
        while node != -1:
            c = cell[node]
            if not seen[c]:
                seen[c] = True
                s = src[node]
                mx = c % nx
                my = c // nx
                sx = s % nx
                sy = s // nx
                cost = cost_cache[abs(mx - sx), abs(my - sy)]
                if min_i <= mx < max_i and min_j <= my < max_j:
                    old = master[my, mx]
                    if old == NO_INFORMATION and (
                            (inflate_unknown and cost > FREE)
                            or (not inflate_unknown and cost >= INSCRIBED)):
                        master[my, mx] = cost
                    elif old != NO_INFORMATION and cost > old:
                        master[my, mx] = cost
                for k in range(4):
                    if k == 0:
                        if mx == 0:
                            continue
                        qx = mx - 1
                        qy = my
                    elif k == 1:
                        if my == 0:
                            continue
                        qx = mx
                        qy = my - 1
                    elif k == 2:
                        if mx == nx - 1:
                            continue
                        qx = mx + 1
                        qy = my
                    else:
                        if my == ny - 1:
                            continue
                        qx = mx
                        qy = my + 1
                    q = qy * nx + qx
                    if seen[q]:
                        continue
                    dx = abs(qx - sx)
                    dy = abs(qy - sy)
                    if dist_cache[dx, dy] > radius or cost_cache[dx, dy] == FREE:
                        continue  # (cost decreases with distance: zero from here on)
                    qb = bin_of[dx, dy]
                    if qb < b:
                        continue
                    if n >= cap:
                        return -1
                    cell[n] = q
                    src[n] = s
                    nxt[n] = -1
                    if tail[qb] == -1:
                        head[qb] = n
                    else:
                        nxt[tail[qb]] = n
                    tail[qb] = n
                    n += 1
            node = nxt[node]
    return n


# --------------------------------------------------------------------------------------------
# Changed region of a grid (the static layer's update bounds)
# --------------------------------------------------------------------------------------------
@numba.njit(cache=True)
def diff_box(new, old):
    """Cells (x0, y0, x1, y1), end-exclusive, bounding where a 2-D grid differs from ``old``
    (a grid of its shape, or one row every row is compared with); (-1, -1, -1, -1) when they
    are equal. A row is first tested whole (a branch-free pass); only a row that differs is
    searched for its first and last differing column."""
    ny, nx = new.shape
    row_step = 1 if old.shape[0] > 1 else 0
    y0 = -1
    y1 = -1
    x0 = nx
    x1 = -1
    for y in range(ny):
        oy = y * row_step
        differs = 0
        for x in range(nx):
            differs |= new[y, x] ^ old[oy, x]
        if differs == 0:
            continue
        if y0 < 0:
            y0 = y
        y1 = y
        x = 0
        while x < x0 and new[y, x] == old[oy, x]:
            x += 1
        x0 = min(x0, x)
        x = nx - 1
        while x > x1 and new[y, x] == old[oy, x]:
            x -= 1
        x1 = max(x1, x)
    if y0 < 0:
        return -1, -1, -1, -1
    return x0, y0, x1 + 1, y1 + 1


def other_box(grid, value):
    """Cells (x0, y0, x1, y1), end-exclusive, bounding the cells of a C-contiguous 2-D grid
    that are not ``value``; (-1, -1, -1, -1) when every cell is (:func:`diff_box` against a
    row of ``value``)."""
    return diff_box(grid, np.full((1, grid.shape[1]), value, grid.dtype))


# --------------------------------------------------------------------------------------------
# Grid search (navfn / global_planner equivalent): 8-connected A* with a goal window
# --------------------------------------------------------------------------------------------
@numba.njit(cache=True, inline="always")
def _heap_rise(keys, vals, i, key, val, past_equal):
    """Put (key, val) into the hole at ``i`` of the binary min-heap, after moving the hole up
    past every parent whose key is larger (also past equal ones when ``past_equal``, a
    constant at each call)."""
    while i > 0:
        parent = (i - 1) >> 1
        if keys[parent] < key or (keys[parent] == key and not past_equal):
            break
        keys[i] = keys[parent]
        vals[i] = vals[parent]
        i = parent
    keys[i] = key
    vals[i] = val


@numba.njit(cache=True, inline="always")
def _heap_push(keys, vals, size, key, val):
    """Push onto the binary min-heap keys[:size]; the caller checks the capacity. The entry
    rises while its parent's key is larger (a hole moves up; the same moves as swapping)."""
    _heap_rise(keys, vals, size, key, val, False)
    return size + 1


@numba.njit(cache=True, inline="always")
def _heap_pop(keys, vals, size):
    """Pop the smallest (key, value); returns (key, value, new size).

    The hole left at the root moves down to a leaf along the smaller children (the left one on
    equal keys), then the last entry rises from there past every parent whose key is >= its
    own. The keys on that path never decrease downwards, so the last entry ends where sinking
    it from the root (past every child with a smaller key) would put it: the same layout, with
    one comparison a level instead of two.
    """
    key = keys[0]
    val = vals[0]
    size -= 1
    last_key = keys[size]
    last_val = vals[size]
    i = 0
    while True:
        left = 2 * i + 1
        if left + 1 < size:
            small = left + (keys[left + 1] < keys[left])
        elif left < size:
            small = left
        else:
            break
        keys[i] = keys[small]
        vals[i] = vals[small]
        i = small
    _heap_rise(keys, vals, i, last_key, last_val, True)
    return key, val, size


@numba.njit(cache=True)
def grid_search(codes, table, sx, sy, gx, gy, win_x0, win_y0, win_x1, win_y1,
                heuristic_weight, keys, vals, g, parent, mark, stamp, size, to_settle, budget):
    """Cheapest 8-connected path from (sx, sy) towards the goal window.

    The cost of entering a cell, per cell of travel (a diagonal step costs sqrt(2) x), is
    ``table[codes[y, x]]`` (``codes`` C-contiguous integer [ny, nx], ``table`` float64);
    ``inf`` = blocked. The start cell is always usable (navfn clears the
    robot cell). The window [win_x0, win_x1] x [win_y0, win_y1] (inclusive, cells) holds the
    acceptable end cells; the search stops as soon as (gx, gy) is settled, or once every
    traversable window cell is settled, or when the queue is empty. The end cell is the settled
    window cell nearest to (gx, gy) (ties: first in row-major order). With a consistent
    heuristic (``heuristic_weight`` <= the smallest cell cost) every settled cell has its
    optimal cost, so the returned path is optimal for its end cell.

    ``keys`` (float64) / ``vals`` (int32) are the heap storage. ``g`` (float64), ``parent`` and
    ``mark`` (int32) are per-cell work arrays of at least ny·nx entries, reused from search to
    search: a cell is reached in this search where ``mark >= 2·stamp`` (then its ``g`` and
    ``parent`` hold) and settled where ``mark == 2·stamp + 1``; ``stamp`` (a search number)
    must exceed every stamp of earlier searches, so nothing needs clearing.

    Pausing: with ``budget`` >= 0 the search pauses before settling more than ``budget``
    cells; it resumes with the same arrays and stamp, ``size`` = the heap entries it left and
    ``to_settle`` = the window cells still to settle (the caller may leave out those no path
    reaches: the search then stops once the others are settled instead of emptying its queue,
    with the same settled window cells, costs and parents). ``size`` 0 starts a search;
    ``to_settle`` -1 counts the window's traversable cells (and the start cell when in it).

    Returns (path as int64 [n, 2] of (x, y) cells from start to end, its cost, status, heap
    entries): status 0 = done (n = 0 when no window cell is reachable), -1 = the heap storage
    was too small (retry with more), 1 = paused.
    """
    ny, nx = codes.shape
    reached = 2 * stamp
    settled = reached + 1
    if to_settle < 0:
        to_settle = 0
        for y in range(max(win_y0, 0), min(win_y1, ny - 1) + 1):
            for x in range(max(win_x0, 0), min(win_x1, nx - 1) + 1):
                if np.isfinite(table[codes[y, x]]) or (x == sx and y == sy):
                    to_settle += 1
    cap = keys.shape[0]
    flat = codes.ravel()
    start = sy * nx + sx
    if size == 0:
        g[start] = 0.0
        mark[start] = reached
        h0 = heuristic_weight * math.hypot(sx - gx, sy - gy)
        size = _heap_push(keys, vals, 0, h0, start)
    diag = math.sqrt(2.0)
    goal_found = False
    while size > 0 and to_settle > 0:
        if budget == 0:
            return np.empty((0, 2), np.int64), np.inf, 1, size
        key, u, size = _heap_pop(keys, vals, size)
        if mark[u] == settled:
            continue
        mark[u] = settled
        budget -= 1
        ux = u % nx
        uy = u // nx
        if win_x0 <= ux <= win_x1 and win_y0 <= uy <= win_y1:
            to_settle -= 1
            if ux == gx and uy == gy:
                goal_found = True
                break
        gu = g[u]
        for dy in range(-1, 2):
            vy = uy + dy
            if vy < 0 or vy >= ny:
                continue
            for dx in range(-1, 2):
                if dx == 0 and dy == 0:
                    continue
                vx = ux + dx
                if vx < 0 or vx >= nx:
                    continue
                v = vy * nx + vx
                c = table[flat[v]]
                if not np.isfinite(c):
                    continue
                m = mark[v]
                if m == settled:
                    continue
                step = diag if dx != 0 and dy != 0 else 1.0
                gv = gu + step * c
                if m != reached or gv < g[v]:
                    mark[v] = reached
                    g[v] = gv
                    parent[v] = u
                    h = heuristic_weight * math.hypot(vx - gx, vy - gy)
                    if size >= cap:
                        return np.empty((0, 2), np.int64), np.inf, -1, size
                    size = _heap_push(keys, vals, size, gv + h, v)
    end = -1
    if goal_found:
        end = gy * nx + gx
    else:
        best = np.inf
        for y in range(max(win_y0, 0), min(win_y1, ny - 1) + 1):
            for x in range(max(win_x0, 0), min(win_x1, nx - 1) + 1):
                idx = y * nx + x
                if mark[idx] == settled:
                    d = (x - gx) * (x - gx) + (y - gy) * (y - gy)
                    if d < best:
                        best = d
                        end = idx
    if end < 0:
        return np.empty((0, 2), np.int64), np.inf, 0, size
    count = 1
    node = end
    while node != start:
        node = parent[node]
        count += 1
    path = np.empty((count, 2), np.int64)
    node = end
    for k in range(count - 1, -1, -1):
        path[k, 0] = node % nx
        path[k, 1] = node // nx
        if k > 0:
            node = parent[node]
    return path, g[end], 0, size


# --------------------------------------------------------------------------------------------
# BFS distance grids (base_local_planner MapGrid::computeTargetDistance)
# --------------------------------------------------------------------------------------------
@numba.njit(cache=True, inline="always")
def _visit(costs, within_robot, dist, qx, qy, nd, unreached, obstacle, queue, tail):
    """BFS step into (qx, qy): obstacle cells get ``obstacle``, free ones ``nd`` and are queued."""
    if dist[qy, qx] != unreached:
        return tail
    c = costs[qy, qx]
    if not within_robot[qy, qx] and (c == LETHAL or c == INSCRIBED or c == NO_INFORMATION):
        dist[qy, qx] = obstacle
        return tail
    dist[qy, qx] = nd
    queue[tail, 0] = qx
    queue[tail, 1] = qy
    return tail + 1


@numba.njit(cache=True)
def target_distance(costs, within_robot, seeds_x, seeds_y, dist, queue, cx, cy, radius):
    """4-connected BFS distance (cells) from the seed cells over a costmap (uint8 [ny, nx]),
    written into ``dist`` (float64 [ny, nx]); ``queue`` (int32 [ny·nx, 2]) is work space.

    Lethal, inscribed and unknown cells (unless inside the robot's footprint) get the obstacle
    value ny·nx and are not expanded; unreached cells keep ny·nx + 1 (base_local_planner's
    obstacleCosts / unreachableCellCosts). Seeds get 0 whatever their cost.

    Only the disk of ``radius`` cells around (cx, cy) is needed (the rollouts never read
    farther): the search stops once every expandable cell of the disk has its distance — BFS
    assigns final values in order, so the disk is exactly as with a full search. radius < 0
    searches everything.
    """
    ny, nx = costs.shape
    obstacle = float(ny * nx)
    unreached = obstacle + 1.0
    dist[:, :] = unreached
    r2 = radius * radius
    need = 0
    if radius >= 0:
        for y in range(max(0, cy - radius), min(ny, cy + radius + 1)):
            for x in range(max(0, cx - radius), min(nx, cx + radius + 1)):
                if (x - cx) * (x - cx) + (y - cy) * (y - cy) <= r2:
                    c = costs[y, x]
                    if within_robot[y, x] or not (c == LETHAL or c == INSCRIBED
                                                  or c == NO_INFORMATION):
                        need += 1
    head = 0
    tail = 0
    for k in range(seeds_x.shape[0]):
        x = seeds_x[k]
        y = seeds_y[k]
        if dist[y, x] == 0.0:
            continue
        dist[y, x] = 0.0
        queue[tail, 0] = x
        queue[tail, 1] = y
        tail += 1
    done = 0
    while head < tail:
        qx0 = queue[head, 0]
        qy0 = queue[head, 1]
        head += 1
        if radius >= 0 and (qx0 - cx) * (qx0 - cx) + (qy0 - cy) * (qy0 - cy) <= r2:
            c0 = costs[qy0, qx0]
            if within_robot[qy0, qx0] or not (c0 == LETHAL or c0 == INSCRIBED
                                              or c0 == NO_INFORMATION):
                done += 1
                if done >= need:
                    break
        nd = dist[qy0, qx0] + 1.0
        if qx0 > 0:
            tail = _visit(costs, within_robot, dist, qx0 - 1, qy0, nd, unreached, obstacle,
                          queue, tail)
        if qx0 < nx - 1:
            tail = _visit(costs, within_robot, dist, qx0 + 1, qy0, nd, unreached, obstacle,
                          queue, tail)
        if qy0 > 0:
            tail = _visit(costs, within_robot, dist, qx0, qy0 - 1, nd, unreached, obstacle,
                          queue, tail)
        if qy0 < ny - 1:
            tail = _visit(costs, within_robot, dist, qx0, qy0 + 1, nd, unreached, obstacle,
                          queue, tail)


# --------------------------------------------------------------------------------------------
# Ray tracing (costmap_2d ObstacleLayer clearing)
# --------------------------------------------------------------------------------------------
@numba.njit(cache=True, inline="always")
def _bresenham_walk(grid, x, y, sxs, sys_, a_major, a_minor, steps, value, x_major):
    """``steps`` Bresenham steps from (x, y) along the dominant axis (x when ``x_major``),
    setting ``value`` on each cell left; returns the cell where it stopped. A constant
    ``x_major`` at each call lets the compiler specialise the loop per axis."""
    ny, nx = grid.shape
    err = a_major // 2
    for _ in range(steps):
        if 0 <= x < nx and 0 <= y < ny:
            grid[y, x] = value
        if x_major:
            x += sxs
        else:
            y += sys_
        err += a_minor
        if err >= a_major:
            if x_major:
                y += sys_
            else:
                x += sxs
            err -= a_major
    return x, y


@numba.njit(cache=True)
def _bresenham_mark(grid, x0, y0, x1, y1, max_len, value):
    """costmap_2d raytraceLine: set ``value`` on the cells from (x0, y0) towards (x1, y1),
    at most ``max_len`` cells of the dominant axis, then on the cell where it stopped."""
    ny, nx = grid.shape
    dx = x1 - x0
    dy = y1 - y0
    adx = abs(dx)
    ady = abs(dy)
    sxs = 1 if dx > 0 else (-1 if dx < 0 else 0)
    sys_ = 1 if dy > 0 else (-1 if dy < 0 else 0)
    dist = math.hypot(dx, dy)
    scale = 1.0 if dist == 0.0 else min(1.0, max_len / dist)
    if adx >= ady:
        steps = min(int(scale * adx), adx)
        x, y = _bresenham_walk(grid, x0, y0, sxs, sys_, adx, ady, steps, value, True)
    else:
        steps = min(int(scale * ady), ady)
        x, y = _bresenham_walk(grid, x0, y0, sxs, sys_, ady, adx, steps, value, False)
    if 0 <= x < nx and 0 <= y < ny:
        grid[y, x] = value


@numba.njit(cache=True)
def obstacle_update(grid, ox, oy, res, sensor_x, sensor_y, points, raytrace_range,
                    obstacle_range, clearing, marking):
    """One laser observation into an obstacle layer (uint8 [ny, nx], origin (ox, oy) m).

    ``points`` (n, 2): world endpoints of the valid returns. Clearing first (raytrace to each
    point, clipped to the map, at most ``raytrace_range``), then marking LETHAL the points
    closer than ``obstacle_range`` — the order of ObstacleLayer::updateBounds.
    """
    ny, nx = grid.shape
    end_x = ox + nx * res
    end_y = oy + ny * res
    if clearing and sensor_x >= ox and sensor_y >= oy and sensor_x < end_x and sensor_y < end_y:
        x0 = int((sensor_x - ox) / res)
        y0 = int((sensor_y - oy) / res)
        cell_range = max(0.0, math.ceil(raytrace_range / res))
        for k in range(points.shape[0]):
            wx = points[k, 0]
            wy = points[k, 1]
            a = wx - sensor_x
            b = wy - sensor_y
            if wx < ox:
                t = (ox - sensor_x) / a
                wx = ox
                wy = sensor_y + b * t
            if wy < oy:
                t = (oy - sensor_y) / b
                wx = sensor_x + a * t
                wy = oy
            if wx > end_x:
                t = (end_x - sensor_x) / a
                wx = end_x - 0.001
                wy = sensor_y + b * t
            if wy > end_y:
                t = (end_y - sensor_y) / b
                wx = sensor_x + a * t
                wy = end_y - 0.001
            if wx < ox or wy < oy:
                continue
            x1 = int((wx - ox) / res)
            y1 = int((wy - oy) / res)
            if x1 >= nx or y1 >= ny:
                continue
            _bresenham_mark(grid, x0, y0, x1, y1, cell_range, FREE)
    if marking:
        sq_range = obstacle_range * obstacle_range
        for k in range(points.shape[0]):
            px = points[k, 0]
            py = points[k, 1]
            if (px - sensor_x) ** 2 + (py - sensor_y) ** 2 >= sq_range:
                continue
            if px < ox or py < oy:
                continue
            mx = int((px - ox) / res)
            my = int((py - oy) / res)
            if mx < nx and my < ny:
                grid[my, mx] = LETHAL


def warmup() -> None:
    """Compile every kernel of the navigation stack on tiny inputs."""
    from slam_predict.nav import rollout
    grid = np.zeros((6, 6), np.uint8)
    grid[2, 2] = LETHAL
    r = 2
    dist = np.hypot(*np.meshgrid(np.arange(r + 2), np.arange(r + 2), indexing="ij"))
    uniq, bins = np.unique(dist, return_inverse=True)
    costs = np.where(dist == 0, LETHAL, INSCRIBED).astype(np.uint8)
    pool = np.empty(200, np.int32)
    inflate(grid, 0, 0, 6, 6, r, costs, dist, bins.reshape(dist.shape).astype(np.int64),
            len(uniq), False, pool, pool.copy(), pool.copy())
    for dtype in (np.int8, np.uint8):    # the SLAM map and the static layer's costs
        diff_box(np.zeros((3, 4), dtype), np.ones((3, 4), dtype))
    grid_search(np.zeros((6, 6), np.uint16), np.ones(258), 0, 0, 5, 5, 5, 5, 5, 5, 1.0,
                np.empty(300), np.empty(300, np.int32), np.empty(36), np.empty(36, np.int32),
                np.zeros(36, np.int32), 1, 0, -1, -1)
    target_distance(grid, np.zeros((6, 6), np.bool_), np.array([0]), np.array([0]),
                    np.empty((6, 6)), np.empty((36, 2), np.int32), 0, 0, -1)
    obstacle_update(grid, 0.0, 0.0, 0.1, 0.05, 0.05, np.array([[0.45, 0.35]]), 3.0, 2.5,
                    True, True)
    rollout.warmup()
