"""Ground-truth coverage of an exploration run and its picture.

Reachable free area: the free cells of the World the robot could occupy — cells whose
clearance exceeds ``robot_radius`` (the navigation footprint's inscribed radius: what the
costmaps let the robot centre use), 8-connected to the start, grown back by that radius and
kept free. Coverage: the share of those cells whose centre falls on a known (not −1) cell of
the final SLAM map.
"""
from __future__ import annotations

import math
import os

import cv2
import numpy as np
from scipy import ndimage

from slam_predict.atomic import write_bytes
from slam_predict.geometry import compose, inverse
from slam_predict.world.model import World


def reachable_free(world: World, robot_radius: float) -> np.ndarray:
    """Bool mask over the World's bitmap of the free area reachable from its start pose."""
    free = ~world.occupied
    clearance = ndimage.distance_transform_edt(free) * world.resolution
    centre_ok = clearance > robot_radius
    labels, count = ndimage.label(centre_ok, structure=np.ones((3, 3), bool))
    if count == 0:
        return np.zeros_like(free)
    row, col = world.world_to_cell(world.start_pose[:2])
    if not (world.in_bounds((row, col)) and labels[row, col]):
        rows, cols = np.nonzero(centre_ok)
        centres = world.cell_to_world(np.stack([rows, cols], axis=1))
        k = int(np.argmin(np.hypot(*(centres - world.start_pose[:2]).T)))
        row, col = rows[k], cols[k]
    component = labels == labels[row, col]
    grow = int(math.ceil(robot_radius / world.resolution))
    if grow > 0:
        component = ndimage.distance_transform_edt(~component) <= grow
    return component & free


def coverage(world: World, grid, reachable: np.ndarray, world_T_map=(0.0, 0.0, 0.0)) -> float:
    """Share (0–1) of ``reachable`` World cells known in ``grid`` (data, origin, resolution)."""
    rows, cols = np.nonzero(reachable)
    if len(rows) == 0:
        return 0.0
    centres = world.cell_to_world(np.stack([rows, cols], axis=1))
    in_map = _to_map(centres, world_T_map)
    data = np.asarray(grid.data)
    gx = np.floor((in_map[:, 0] - grid.origin[0]) / grid.resolution).astype(int)
    gy = np.floor((in_map[:, 1] - grid.origin[1]) / grid.resolution).astype(int)
    inside = (gx >= 0) & (gx < data.shape[1]) & (gy >= 0) & (gy < data.shape[0])
    known = np.zeros(len(rows), bool)
    known[inside] = data[gy[inside], gx[inside]] != -1
    return float(known.mean())


def _to_map(points_world: np.ndarray, world_T_map) -> np.ndarray:
    """World points (n, 2) expressed in the map frame."""
    map_T_world = inverse(np.asarray(world_T_map, dtype=float))
    poses = np.column_stack([points_world, np.zeros(len(points_world))])
    return compose(map_T_world, poses)[:, :2]


def render_png(path: os.PathLike | str, grid, path_xy: np.ndarray, world_T_map=(0.0, 0.0, 0.0),
               max_side: int = 2000) -> None:
    """Write the map (white free, black occupied, grey unknown) with the robot's path in red
    (``path_xy`` (n, 2) in the world frame) as a PNG, atomically."""
    data = np.asarray(grid.data)
    img = np.full(data.shape + (3,), 205, np.uint8)
    img[data == 0] = 254
    img[data == 100] = 0
    img = np.ascontiguousarray(img[::-1])
    scale = 1
    while max(img.shape[:2]) * (scale + 1) <= max_side and scale < 4:
        scale += 1
    if scale > 1:
        img = cv2.resize(img, None, fx=scale, fy=scale, interpolation=cv2.INTER_NEAREST)
    if len(path_xy) > 1:
        xy = _to_map(np.asarray(path_xy, dtype=float), world_T_map)
        px = (xy[:, 0] - grid.origin[0]) / grid.resolution * scale
        py = (data.shape[0] - (xy[:, 1] - grid.origin[1]) / grid.resolution) * scale
        pts = np.round(np.stack([px, py], axis=1)).astype(np.int32).reshape(-1, 1, 2)
        cv2.polylines(img, [pts], False, (0, 0, 255), max(1, scale // 2), cv2.LINE_AA)
        cv2.circle(img, tuple(int(v) for v in pts[0, 0]), 3 * scale, (0, 160, 0), -1)
        cv2.circle(img, tuple(int(v) for v in pts[-1, 0]), 3 * scale, (255, 0, 0), -1)
    ok, encoded = cv2.imencode(".png", img)
    if not ok:
        raise OSError(f"could not encode {path}")
    write_bytes(path, encoded.tobytes())
