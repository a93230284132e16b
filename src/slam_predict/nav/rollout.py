"""numba kernels of base_local_planner's trajectory rollout (TrajectoryPlanner::generateTrajectory).

A sample (vx, vθ) is simulated for ``sim_time`` from the current pose and velocity, ramping the
velocity towards the sample with the acceleration limits; every point is checked with the
footprint (CostmapModel::footprintCost: the polygon outline rasterised with base_local_planner's
line iterator; LETHAL or NO_INFORMATION cells make it illegal). Cost of a legal trajectory:
``pdist·path_dist + gdist·goal_dist + occdist·max cell cost`` (distances of its last point).
Costs: -1 = footprint hits an obstacle or leaves the map, -2 = a point has no path to the goal.
"""
from __future__ import annotations

import math

import numba
import numpy as np

LETHAL = 254
NO_INFORMATION = 255


@numba.njit(cache=True)
def _line_cost(costs, x0, y0, x1, y1):
    """Max cost along a line of cells (base_local_planner LineIterator); -1 if it hits
    LETHAL or NO_INFORMATION."""
    dx = abs(x1 - x0)
    dy = abs(y1 - y0)
    xinc1 = 1 if x1 >= x0 else -1
    xinc2 = xinc1
    yinc1 = 1 if y1 >= y0 else -1
    yinc2 = yinc1
    if dx >= dy:
        xinc1 = 0
        yinc2 = 0
        den = dx
        num = dx // 2
        numadd = dy
        numpixels = dx
    else:
        xinc2 = 0
        yinc1 = 0
        den = dy
        num = dy // 2
        numadd = dx
        numpixels = dy
    x = x0
    y = y0
    line = 0.0
    for _ in range(numpixels + 1):
        c = costs[y, x]
        if c == LETHAL or c == NO_INFORMATION:
            return -1.0
        if c > line:
            line = float(c)
        num += numadd
        if num >= den:
            num -= den
            x += xinc1
            y += yinc1
        x += xinc2
        y += yinc2
    return line


@numba.njit(cache=True)
def footprint_vertex_cells(ox, oy, res, nx, ny, x, y, th, footprint, cells):
    """Cells (k, 2) of the polygon's vertices at pose (x, y, th) written into ``cells``;
    False when a vertex (or the pose) is off the map."""
    if x < ox or y < oy or int((x - ox) / res) >= nx or int((y - oy) / res) >= ny:
        return False
    c = math.cos(th)
    s = math.sin(th)
    for i in range(footprint.shape[0]):
        px = x + footprint[i, 0] * c - footprint[i, 1] * s
        py = y + footprint[i, 0] * s + footprint[i, 1] * c
        if px < ox or py < oy:
            return False
        cx = int((px - ox) / res)
        cy = int((py - oy) / res)
        if cx >= nx or cy >= ny:
            return False
        cells[i, 0] = cx
        cells[i, 1] = cy
    return True


@numba.njit(cache=True)
def outline_cost(costs, cells):
    """Max cost along the closed outline through the vertex cells (k, 2), edge by edge from
    the last vertex; -1 when it touches LETHAL or NO_INFORMATION."""
    k = cells.shape[0]
    total = 0.0
    x0 = cells[k - 1, 0]
    y0 = cells[k - 1, 1]
    for i in range(k):
        x1 = cells[i, 0]
        y1 = cells[i, 1]
        line = _line_cost(costs, x0, y0, x1, y1)
        if line < 0:
            return -1.0
        if line > total:
            total = line
        x0 = x1
        y0 = y1
    return total


@numba.njit(cache=True)
def footprint_cost(costs, ox, oy, res, x, y, th, footprint):
    """CostmapModel::footprintCost of the polygon ``footprint`` (k, 2) at pose (x, y, th)."""
    ny, nx = costs.shape
    cells = np.empty((footprint.shape[0], 2), np.int64)
    if not footprint_vertex_cells(ox, oy, res, nx, ny, x, y, th, footprint, cells):
        return -1.0
    return outline_cost(costs, cells)


@numba.njit(cache=True, inline="always")
def _same_cells(a, b):
    for i in range(a.shape[0]):
        if a[i, 0] != b[i, 0] or a[i, 1] != b[i, 1]:
            return False
    return True


@numba.njit(cache=True)
def _new_velocity(vg, vi, a_max, dt):
    if vg - vi >= 0:
        return min(vg, vi + a_max * dt)
    return max(vg, vi - a_max * dt)


@numba.njit(cache=True)
def rollout(x, y, th, vx, vth, vx_samp, vth_samp, acc_x, acc_th, sim_time, gran, agran,
            costs, ox, oy, res, footprint, path_dist, goal_dist, impossible, pdist, gdist,
            occdist, points):
    """Simulate and score one sample. ``points`` (m, 3) receives the poses when m is large
    enough (else nothing is recorded). Returns (cost, number of points, end x, y, th) where
    the end is the last legal point."""
    ny, nx = costs.shape
    num_steps = int(max(abs(vx_samp) * sim_time / gran, abs(vth_samp) / agran) + 0.5)
    if num_steps == 0:
        num_steps = 1
    dt = sim_time / num_steps
    xi = x
    yi = y
    thi = th
    vxi = vx
    vthi = vth
    path_d = 0.0
    goal_d = 0.0
    occ = 0.0
    ex = x
    ey = y
    eth = th
    record = points.shape[0] >= num_steps
    # the footprint cost depends only on the vertex cells: a step on the same cells as the
    # previous step reuses it
    cells = np.empty((footprint.shape[0], 2), np.int64)
    last = np.full((footprint.shape[0], 2), -1, np.int64)
    fc = -1.0
    for i in range(num_steps):
        if xi < ox or yi < oy:
            return -1.0, i, ex, ey, eth
        cx = int((xi - ox) / res)
        cy = int((yi - oy) / res)
        if cx >= nx or cy >= ny:
            return -1.0, i, ex, ey, eth
        if not footprint_vertex_cells(ox, oy, res, nx, ny, xi, yi, thi, footprint, cells):
            return -1.0, i, ex, ey, eth
        if not _same_cells(cells, last):
            fc = outline_cost(costs, cells)
            last[:, :] = cells
        if fc < 0:
            return -1.0, i, ex, ey, eth
        occ = max(occ, fc, float(costs[cy, cx]))
        path_d = path_dist[cy, cx]
        goal_d = goal_dist[cy, cx]
        if impossible <= goal_d or impossible <= path_d:
            return -2.0, i, ex, ey, eth
        ex = xi
        ey = yi
        eth = thi
        if record:
            points[i, 0] = xi
            points[i, 1] = yi
            points[i, 2] = thi
        vxi = _new_velocity(vx_samp, vxi, acc_x, dt)
        vthi = _new_velocity(vth_samp, vthi, acc_th, dt)
        xi = xi + vxi * math.cos(thi) * dt
        yi = yi + vxi * math.sin(thi) * dt
        thi = thi + vthi * dt
    cost = pdist * path_d + gdist * goal_d + occdist * occ
    return cost, num_steps, ex, ey, eth


@numba.njit(cache=True)
def score_samples(samples, x, y, th, vx, vth, acc_x, acc_th, sim_time, gran, agran, costs,
                  ox, oy, res, footprint, path_dist, goal_dist, impossible, pdist, gdist,
                  occdist):
    """Rollout costs (n,) and end poses (n, 3) of the samples (n, 2) = (vx, vθ)."""
    n = samples.shape[0]
    out = np.empty(n)
    ends = np.empty((n, 3))
    none = np.empty((0, 3))
    for k in range(n):
        cost, _, ex, ey, eth = rollout(x, y, th, vx, vth, samples[k, 0], samples[k, 1], acc_x,
                                       acc_th, sim_time, gran, agran, costs, ox, oy, res,
                                       footprint, path_dist, goal_dist, impossible, pdist,
                                       gdist, occdist, none)
        out[k] = cost
        ends[k, 0] = ex
        ends[k, 1] = ey
        ends[k, 2] = eth
    return out, ends


@numba.njit(cache=True)
def forward_samples(min_vx, dvx, min_vth, dvth, nvx, nvth):
    """(vx m/s, vθ rad/s) samples (nvx·max(nvth, 1), 2) in createTrajectories' order: per vx
    (min_vx, then + dvx each time), vθ = 0, then nvth − 1 values from min_vth (+ dvth each)."""
    per_vx = 1 + max(nvth - 1, 0)
    out = np.empty((nvx * per_vx, 2))
    k = 0
    vx = min_vx
    for _ in range(nvx):
        out[k, 0] = vx
        out[k, 1] = 0.0
        k += 1
        v = min_vth
        for _ in range(nvth - 1):
            out[k, 0] = vx
            out[k, 1] = v
            k += 1
            v += dvth
        vx += dvx
    return out


@numba.njit(cache=True)
def first_cheapest(costs):
    """Index of the first legal (cost ≥ 0) entry of least cost, or -1 when none is legal."""
    best = -1
    best_cost = -1.0
    for k in range(costs.shape[0]):
        if costs[k] >= 0 and (costs[k] < best_cost or best_cost < 0):
            best = k
            best_cost = costs[k]
    return best


def warmup() -> None:
    """Compile the rollout kernels on a tiny costmap."""
    costs = np.zeros((20, 20), np.uint8)
    dist = np.zeros((20, 20))
    fp = np.array([[-0.1, -0.1], [-0.1, 0.1], [0.1, 0.1], [0.1, -0.1]])
    samples = np.array([[0.1, 0.0], [0.0, 0.5]])
    score_samples(samples, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 0.025, 0.025, costs, 0.0,
                  0.0, 0.1, fp, dist, dist, 400.0, 0.6, 0.8, 0.01)
    rollout(1.0, 1.0, 0.0, 0.0, 0.0, 0.1, 0.0, 1.0, 1.0, 1.0, 0.025, 0.025, costs, 0.0, 0.0,
            0.1, fp, dist, dist, 400.0, 0.6, 0.8, 0.01, np.empty((100, 3)))
    footprint_cost(costs, 0.0, 0.0, 0.1, 1.0, 1.0, 0.0, fp)
    first_cheapest(score_samples(forward_samples(0.1, 0.1, -0.5, 0.5, 2, 3), 1.0, 1.0, 0.0, 0.0,
                                 0.0, 1.0, 1.0, 1.0, 0.025, 0.025, costs, 0.0, 0.0, 0.1, fp,
                                 dist, dist, 400.0, 0.6, 0.8, 0.01)[0])
