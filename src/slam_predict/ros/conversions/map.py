"""World / occupancy grids ↔ ``nav_msgs/OccupancyGrid``.

Conventions of the message (map_server, gmapping): cell values 0 = free, 100 = occupied,
−1 = unknown; ``info.origin`` is the map-frame pose of the corner of cell (0, 0); data are
row-major with row 0 at the BOTTOM (smallest y). Our bitmaps have row 0 at the top and are
centred on ``origin`` (world xy of the bitmap centre), so rows are flipped and the corner is
origin − (W/2, H/2). Our world frame is used as the map frame (no rotation).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from slam_predict.geometry import quaternion_to_yaw, yaw_to_quaternion
from slam_predict.world.model import World

FREE, OCCUPIED, UNKNOWN = 0, 100, -1


@dataclass(eq=False)
class OccupancyMap:
    """A ROS-style occupancy grid in our orientation.

    Attributes:
        values: int8 (rows, cols), row 0 = top; 0 free, 100 occupied, −1 unknown (0..100 allowed).
        resolution: m per cell.
        origin: world (x, y) of the grid centre, m (as :attr:`World.origin`).
        frame_id: the TF frame of the grid.
    """

    values: np.ndarray
    resolution: float
    origin: tuple[float, float] = (0.0, 0.0)
    frame_id: str = "map"
    stamp: object | None = field(default=None, compare=False)

    def occupied(self, unknown_is_occupied: bool = True, threshold: int = 50) -> np.ndarray:
        """Bool occupancy: cells ≥ ``threshold`` (and unknown ones, by default) are obstacles."""
        occ = self.values >= threshold
        return occ | (self.values < 0) if unknown_is_occupied else occ

    def to_world(self, name: str = "map") -> World:
        """A World (unknown counts as obstacle) with this grid's frame."""
        return World(name=name, occupied=self.occupied(), resolution=self.resolution,
                     origin=self.origin, provenance={"format": "ros-occupancy-grid"})


def world_values(world: World) -> np.ndarray:
    """int8 grid of a World: 100 where occupied, 0 where free (row 0 = top)."""
    return np.where(world.occupied, OCCUPIED, FREE).astype(np.int8)


def occupancy_to_ros(grid, frame_id: str | None = None, stamp=None):
    """A ``nav_msgs/OccupancyGrid`` from a :class:`World` or an :class:`OccupancyMap`.

    ``frame_id`` defaults to the OccupancyMap's frame ("map" for a World).
    """
    from nav_msgs.msg import OccupancyGrid

    if isinstance(grid, World):
        grid = OccupancyMap(world_values(grid), grid.resolution, tuple(grid.origin))
    values = np.asarray(grid.values)
    if values.ndim != 2:
        raise ValueError("occupancy values must be a 2-D array")
    if values.min(initial=0) < -1 or values.max(initial=0) > 100:
        raise ValueError("occupancy values must lie in -1..100")
    rows, cols = values.shape
    msg = OccupancyGrid()
    msg.header.frame_id = grid.frame_id if frame_id is None else frame_id
    if stamp is not None:
        msg.header.stamp = stamp
        msg.info.map_load_time = stamp
    msg.info.resolution = float(grid.resolution)
    msg.info.width, msg.info.height = int(cols), int(rows)
    msg.info.origin.position.x = float(grid.origin[0] - cols * grid.resolution / 2.0)
    msg.info.origin.position.y = float(grid.origin[1] - rows * grid.resolution / 2.0)
    qx, qy, qz, qw = yaw_to_quaternion(0.0)
    o = msg.info.origin.orientation
    o.x, o.y, o.z, o.w = float(qx), float(qy), float(qz), float(qw)
    msg.data = np.flipud(values).astype(np.int8).ravel().tolist()
    return msg


def occupancy_from_ros(msg) -> OccupancyMap:
    """An :class:`OccupancyMap` (row 0 = top, centre origin) from a ``nav_msgs/OccupancyGrid``."""
    info = msg.info
    rows, cols = int(info.height), int(info.width)
    data = np.asarray(msg.data, dtype=np.int8)
    if data.size != rows * cols:
        raise ValueError(f"OccupancyGrid has {data.size} cells, expected {rows} x {cols}")
    o = info.origin.orientation
    yaw = quaternion_to_yaw(o.x, o.y, o.z, o.w) if (o.x, o.y, o.z, o.w) != (0, 0, 0, 0) else 0.0
    if abs(float(yaw)) > 1e-9:
        raise ValueError("rotated OccupancyGrid origins are not supported")
    values = np.flipud(data.reshape(rows, cols)).copy()
    res = float(info.resolution)
    origin = (info.origin.position.x + cols * res / 2.0, info.origin.position.y + rows * res / 2.0)
    return OccupancyMap(values, res, origin, msg.header.frame_id, msg.header.stamp)
