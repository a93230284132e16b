"""The one start-pose rule shared by every command that takes a plan.

Default start: the centre of the free cell of largest clearance (distance to the nearest
obstacle), ties broken by the smallest row-major index, yaw 0. ``--start X Y [YAW]`` gives the
pose in metres and degrees in the Stage frame; ``--snap-start`` moves a pose that is in a wall
(or too close to one for the robot's footprint) to the nearest cell with enough clearance.
"""
from __future__ import annotations

import logging
import math
from collections.abc import Sequence

import numpy as np
from scipy import ndimage

from slam_predict.errors import InputError
from slam_predict.world.model import World

LOG = logging.getLogger(__name__)


def clearance_m(world: World) -> np.ndarray:
    """Distance in m from each free cell centre to the nearest occupied cell (0 on obstacles)."""
    return ndimage.distance_transform_edt(~world.occupied) * world.resolution


def default_start(world: World) -> np.ndarray:
    """(x, y, yaw) of the free cell centre with the largest clearance, yaw 0."""
    clear = clearance_m(world)
    index = int(np.argmax(clear))
    if clear.flat[index] <= 0:
        raise InputError("no free cell for a start pose", world.provenance.get("source"))
    row, col = np.unravel_index(index, clear.shape)
    x, y = world.cell_to_world((row, col))
    return np.array([x, y, 0.0])


def robot_radius(world: World) -> float:
    """Half the footprint side, m: the clearance below which a start pose is moved."""
    return world.robot.footprint_side / 2.0


def start_clearance(world: World) -> float:
    """Clearance (m, between cell centres) that keeps the square footprint, at any yaw, off
    every occupied cell: its circumscribed radius plus half a cell's diagonal."""
    return math.sqrt(2.0) * (world.robot.footprint_side + world.resolution) / 2.0


def snap_to_free(world: World, pose: np.ndarray) -> np.ndarray:
    """Move ``pose`` to the nearest cell centre from which the footprint touches no obstacle
    at any yaw (:func:`start_clearance`)."""
    clear = clearance_m(world)
    ok = clear > start_clearance(world)
    if not ok.any():
        ok = clear > 0
    rows, cols = np.nonzero(ok)
    centres = world.cell_to_world(np.stack([rows, cols], axis=1))
    best = int(np.argmin(np.hypot(centres[:, 0] - pose[0], centres[:, 1] - pose[1])))
    snapped = np.array([centres[best, 0], centres[best, 1], pose[2]])
    LOG.warning("start pose (%.2f, %.2f) snapped to (%.2f, %.2f)", pose[0], pose[1],
                snapped[0], snapped[1])
    return snapped


def parse_start(values: Sequence[float] | None) -> np.ndarray | None:
    """``--start X Y [YAW]`` (m, m, deg) → (x, y, yaw rad), or None when not given."""
    if values is None:
        return None
    if len(values) not in (2, 3):
        raise InputError("--start takes X Y [YAW] (metres, metres, degrees)")
    yaw = math.radians(values[2]) if len(values) == 3 else 0.0
    return np.array([float(values[0]), float(values[1]), yaw])


def check_start(world: World, pose: np.ndarray, source: str | None = None) -> None:
    """Raise InputError when ``pose`` is outside the map or inside a wall."""
    rc = world.world_to_cell(pose[:2])
    if not world.in_bounds(rc):
        raise InputError(f"start pose ({pose[0]:.2f}, {pose[1]:.2f}) is outside the map "
                         f"({world.size_m[0]:.2f} x {world.size_m[1]:.2f} m)", source)
    if world.occupied[rc[0], rc[1]]:
        raise InputError(f"start pose ({pose[0]:.2f}, {pose[1]:.2f}) is inside a wall "
                         "(use --snap-start)", source)


def resolve_start(world: World, start: Sequence[float] | None = None,
                  snap: bool = False) -> World:
    """Apply the start-pose rule: explicit ``start`` (m, m, deg), else the world's, else default.

    Returns a World whose ``start_pose`` is valid; raises InputError for a pose in a wall or
    outside the map unless ``snap`` is set.
    """
    source = world.provenance.get("source")
    pose = parse_start(start)
    if pose is None:
        pose = world.start_pose if world.provenance.get("start_given") else default_start(world)
    rc = world.world_to_cell(pose[:2])
    inside = bool(world.in_bounds(rc))
    if snap and (not inside or world.occupied[rc[0], rc[1]]
                 or clearance_m(world)[rc[0], rc[1]] <= robot_radius(world)):
        pose = snap_to_free(world, pose)
    check_start(world, pose, source)
    return world.replace(start_pose=pose)
