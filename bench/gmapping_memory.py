"""Memory benchmark of the GMapping port (run by ``bench/bench_gmapping.py --memory``).

A simulated robot drives a tour of ipa's lab_a at the seed thesis' scale (0.1 m/px, 82.4 m x
70.8 m ≈ 5,800 m²) with the thesis laser (270°, 0.5°, 541 beams) and odometry error; GMapping
runs with config/gmapping.yaml (40 particles, maxUrange 30 m). Prints the processed scans, CPU
time, patches in use and the process's peak RSS (target ≤ 1.5 GB).
"""
from __future__ import annotations

import argparse
import os
import resource
import time
from pathlib import Path

import numpy as np
from scipy import ndimage
from skimage.graph import MCP_Geometric

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("SLAM_PREDICT_SHARED", ROOT.parent / "shared"))
PLAN = SHARED / "data" / "floorplans" / "ipa" / "lab_a_scan.png"
RES = 0.1  # m/px, the thesis' scale for lab_a


def tour(free: np.ndarray, n_goals: int, rng: np.random.Generator) -> np.ndarray:
    """(N, 2) cell path (row, col) visiting random goals with ≥ 0.6 m clearance, nearest first."""
    clearance = ndimage.distance_transform_edt(free) * RES
    labels, _ = ndimage.label(clearance > 0.6)
    biggest = np.argmax(np.bincount(labels.ravel())[1:]) + 1
    cells = np.argwhere(labels == biggest)
    goals = cells[rng.choice(len(cells), n_goals, replace=False)]
    cost = np.where(labels == biggest, 1.0 + 2.0 / np.maximum(clearance, 0.1), np.inf)
    path = [goals[0]]
    todo = list(goals[1:])
    while todo:
        here = path[-1]
        k = int(np.argmin([np.hypot(*(g - here)) for g in todo]))
        goal = todo.pop(k)
        mcp = MCP_Geometric(cost)
        mcp.find_costs([tuple(here)], [tuple(goal)])
        path.extend(np.array(mcp.traceback(tuple(goal)))[1:])
    return np.array(path)


def poses_along(path_cells: np.ndarray, rows: int, cols: int, step: float) -> np.ndarray:
    """World poses (x, y, yaw) every ``step`` m along a smoothed cell path (bitmap centred)."""
    xy = np.c_[(path_cells[:, 1] + 0.5) * RES - cols * RES / 2,
               rows * RES / 2 - (path_cells[:, 0] + 0.5) * RES]
    xy = ndimage.uniform_filter1d(xy, 9, axis=0, mode="nearest")
    seg = np.r_[0.0, np.cumsum(np.hypot(*np.diff(xy, axis=0).T))]
    s = np.arange(0.0, seg[-1], step)
    x, y = np.interp(s, seg, xy[:, 0]), np.interp(s, seg, xy[:, 1])
    yaw = np.unwrap(np.arctan2(np.gradient(y), np.gradient(x)))
    return np.c_[x, y, yaw]


def main() -> None:
    from slam_predict.geometry import compose, inverse
    from slam_predict.sim.raycast import GridFrame, LaserGrid
    from slam_predict.slam import LaserGeometry
    from slam_predict.slam.gmapping.filter import GMapping
    from slam_predict.slam.gmapping.params import load_params
    from slam_predict.world.bitmap import load_occupancy

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--memory", action="store_true")
    parser.add_argument("--goals", type=int, default=60, help="tour waypoints")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    occupied = load_occupancy(PLAN)
    rows, cols = occupied.shape
    truth = poses_along(tour(~occupied, args.goals, rng), rows, cols, step=0.1)
    grid_sim = LaserGrid(occupied, GridFrame(-cols * RES / 2, rows * RES / 2, RES))
    angles = np.radians(np.linspace(-135.0, 135.0, 541))
    ca, sa = np.cos(angles), np.sin(angles)
    params = load_params(ROOT / "config" / "gmapping.yaml")
    slam = GMapping(params, LaserGeometry(angles, (0.0, 0.0, 0.0), 60.0), rng)
    odom = truth[0].copy()
    cpu0 = time.process_time()
    for k in range(len(truth)):
        if k:
            step = compose(inverse(truth[k - 1]), truth[k])
            step[0] *= 1.0 + rng.uniform(-0.005, 0.005)
            step[2] += np.radians(1.0) * abs(step[2]) + 0.001 * step[0]
            odom = compose(odom, step)
        ranges = grid_sim.scan(truth[k, 0], truth[k, 1], truth[k, 2], ca, sa, 60.0)
        slam.update(odom, ranges, 0.1 * k)
    cpu = time.process_time() - cpu0
    grid = slam.map()
    stats = slam.stats()
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    path_m = float(np.sum(np.hypot(*np.diff(truth[:, :2], axis=0).T)))
    print(f"lab_a at {RES} m/px: {cols * RES:.1f} m x {rows * RES:.1f} m "
          f"({cols * rows * RES * RES:.0f} m²), tour {path_m:.0f} m, {len(truth)} scans")
    print(f"40 particles: {stats['scans_processed']} scans processed, {stats['resamples']} "
          f"resamples, CPU {cpu:.0f} s, patches in use {stats['patches_in_use']} "
          f"(pool {stats['patch_pool_mib']:.0f} MiB), map {grid.width}x{grid.height}")
    print(f"peak RSS {rss:.0f} MiB (target <= 1536 MiB)")


if __name__ == "__main__":
    main()
