"""The floor a run's laser swept, from the ground truth: exploration coverage without the map.

:func:`slam_predict.explore.coverage.coverage` counts the reachable cells that fall on known
cells of the final SLAM map, placed with the map frame on the start pose. When the SLAM estimate
has drifted by metres, parts the robot did see lie beside where the map puts them, and that
count mixes the map's error into the exploration's. Here a cell is *swept* when a beam cast
from a true laser pose in the World's bitmap crossed it before reaching an occupied cell or the
SLAM back-end's usable range (GMapping's ``maxUrange``: farther beam ends add no free cells to
its map). The Stage laser is exact, so these are the beams the robot got.

Each run record holds :func:`swept_coverage` as ``coverage_swept``: the poses are the
ground-truth trajectory's, one every :data:`SWEEP_STEP_M` of path or :data:`SWEEP_STEP_RAD` of
turn (the ROS path's orchestrator observes them too); ``bench/bench_coverage_timeline.py``
sweeps from the true poses of the scans the back-end processed instead.
"""
from __future__ import annotations

import math

import numba
import numpy as np

from slam_predict.geometry import compose
from slam_predict.sim.raycast import axis_walk, next_cell


@numba.njit(cache=True, nogil=True)
def mark_beams(seen, occ, x_left, y_top, res, px, py, yaw, cos_a, sin_a, reach_m):
    """Set ``seen`` (bool, the bitmap's shape) on every free cell that the beams (bearings with
    cosines/sines ``cos_a``/``sin_a`` in the laser frame) from world (px, py, yaw) cross
    before they enter an occupied cell or leave the bitmap, within ``reach_m`` (m).
    The Amanatides–Woo cell walk of :func:`slam_predict.sim.raycast.cast_scan`."""
    rows, cols = occ.shape
    gx = (px - x_left) / res
    gy = (y_top - py) / res
    t_max = reach_m / res
    cy, sy = math.cos(yaw), math.sin(yaw)
    for i in range(cos_a.shape[0]):
        dgx = cy * cos_a[i] - sy * sin_a[i]
        dgy = -(sy * cos_a[i] + cy * sin_a[i])
        col, row = int(math.floor(gx)), int(math.floor(gy))
        step_c, delta_c, next_c = axis_walk(dgx, gx, col, 0.0)
        step_r, delta_r, next_r = axis_walk(dgy, gy, row, 0.0)
        t = 0.0
        while 0 <= row < rows and 0 <= col < cols and not occ[row, col] and t < t_max:
            seen[row, col] = True
            t, col, row, next_c, next_r = next_cell(col, row, step_c, step_r, delta_c, delta_r,
                                                    next_c, next_r)


def seen_mask(world, robot_poses: np.ndarray, laser_pose, angles: np.ndarray,
              reach_m: float) -> np.ndarray:
    """Bool mask over the World's bitmap of the free cells the laser swept from the robot's
    true poses ``robot_poses`` (n, 3; world frame) with the laser at ``laser_pose`` (x, y, yaw
    on the robot) and beams at ``angles`` (rad), each beam up to ``reach_m`` (m)."""
    from slam_predict.sim.raycast import GridFrame

    frame = GridFrame.of_world(world)
    occ = np.ascontiguousarray(world.occupied, dtype=bool)
    seen = np.zeros(occ.shape, dtype=bool)
    angles = np.asarray(angles, dtype=float)
    cos_a, sin_a = np.cos(angles), np.sin(angles)
    lasers = compose(np.asarray(robot_poses, float).reshape(-1, 3), np.asarray(laser_pose, float))
    for x, y, yaw in lasers:
        mark_beams(seen, occ, frame.x_left, frame.y_top, frame.resolution, float(x), float(y),
                   float(yaw), cos_a, sin_a, float(reach_m))
    return seen


def seen_share(reachable: np.ndarray, seen: np.ndarray) -> float:
    """Share (0–1) of the ``reachable`` cells that are ``seen``."""
    total = int(reachable.sum())
    return float((reachable & seen).sum() / total) if total else 0.0


def poses_at(times: np.ndarray, track_times: np.ndarray, track: np.ndarray) -> np.ndarray:
    """Poses (n, 3) of a trajectory (``track_times`` ascending, ``track`` (m, 3)) at ``times``:
    the latest pose at or before each time (the ground truth is logged with every scan)."""
    index = np.searchsorted(track_times, np.asarray(times) + 1e-9, side="right") - 1
    return track[np.clip(index, 0, len(track) - 1)]


SWEEP_STEP_M = 0.25      # m: a ground-truth pose is swept from once the robot moved this far
SWEEP_STEP_RAD = 0.25    # rad: ... or turned this much since the last pose swept from


def sweep_poses(poses: np.ndarray) -> np.ndarray:
    """The poses (n, 3) of a trajectory to sweep from: the first, then each one that is
    :data:`SWEEP_STEP_M` or :data:`SWEEP_STEP_RAD` from the last kept (a robot standing or
    creeping adds nothing)."""
    poses = np.asarray(poses, dtype=float).reshape(-1, 3)
    if len(poses) == 0:
        return poses
    kept = [0]
    for i in range(1, len(poses)):
        last = poses[kept[-1]]
        turn = abs(math.remainder(poses[i, 2] - last[2], 2 * math.pi))
        if math.hypot(*(poses[i, :2] - last[:2])) >= SWEEP_STEP_M or turn >= SWEEP_STEP_RAD:
            kept.append(i)
    return poses[kept]


def usable_range(slam_params, laser_range_max: float) -> float:
    """m: how far a beam adds free cells to the SLAM map: the laser's range, capped by
    GMapping's ``maxUrange`` or Karto's ``max_laser_range`` when ``slam_params`` sets one (None:
    the laser's range, as slam_gmapping takes it)."""
    cap = getattr(slam_params, "maxUrange", getattr(slam_params, "max_laser_range", None))
    return float(laser_range_max) if cap is None else min(float(laser_range_max), float(cap))


def swept_coverage(world, reachable: np.ndarray, truth_poses: np.ndarray, laser,
                   reach_m: float) -> float:
    """Share (0–1) of the ``reachable`` floor that the laser (a
    :class:`slam_predict.sensor.LaserConfig`) swept from the ground-truth trajectory
    ``truth_poses`` (n, 3; world frame), each beam up to ``reach_m`` (m)."""
    seen = seen_mask(world, sweep_poses(truth_poses), laser.pose, laser.angles(), reach_m)
    return seen_share(reachable, seen)
