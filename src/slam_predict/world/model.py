"""The World: an occupancy bitmap in metres, with robot, laser and start pose.

Frames follow Stage: world x to the right, y up, the bitmap centred on ``origin`` (the
floorplan pose, usually (0, 0)). Row 0 of the bitmap is its top (largest y).
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from slam_predict.errors import InputError
from slam_predict.sensor import LaserConfig

DEG = math.pi / 180.0


LaserSpec = LaserConfig  # the World's laser (from the Stage file) is a sensor.LaserConfig


@dataclass
class RobotSpec:
    """A differential-drive robot: square footprint (m), limits (m/s, rad/s, m/s², rad/s²)."""

    footprint_side: float = 0.3
    max_vel_x: float = 1.0
    max_vel_theta: float = 90.0 * DEG
    max_acc_x: float = 1.5
    max_acc_theta: float = 0.0  # 0 = unlimited, as Stage
    odom_error: tuple[float, float, float, float] = (0.01, 0.01, 0.0, 2.0 * DEG)
    localization: str = "odom"
    drive: str = "diff"


@dataclass
class Room:
    """A ground-truth space: polygon (N, 2) in world metres, a label, an id."""

    id: str
    polygon: np.ndarray
    label: str = ""


@dataclass
class Door:
    """A ground-truth passage: segment endpoints (2, 2) in world metres, the two room ids."""

    segment: np.ndarray
    rooms: tuple[str, str] = ("", "")


@dataclass
class World:
    """An environment for simulation and feature extraction.

    Attributes:
        name: short identifier (used for folders).
        occupied: bool array (rows, cols); True = obstacle or outside the building.
        resolution: metres per pixel (square pixels).
        start_pose: (x, y, yaw) in m, m, rad in the world frame.
        origin: world (x, y) of the bitmap centre, m.
    """

    name: str
    occupied: np.ndarray
    resolution: float
    start_pose: np.ndarray = field(default_factory=lambda: np.zeros(3))
    origin: tuple[float, float] = (0.0, 0.0)
    robot: RobotSpec = field(default_factory=RobotSpec)
    laser: LaserSpec = field(default_factory=LaserSpec)
    interval_sim: float = 0.1
    rooms: list[Room] = field(default_factory=list)
    doors: list[Door] = field(default_factory=list)
    provenance: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.occupied = np.ascontiguousarray(self.occupied, dtype=bool)
        self.start_pose = np.asarray(self.start_pose, dtype=float).reshape(3)
        if self.occupied.ndim != 2:
            raise ValueError("occupied must be a 2-D array")
        if not self.resolution > 0:
            raise ValueError("resolution must be > 0")

    @property
    def shape(self) -> tuple[int, int]:
        """(rows, cols) of the bitmap."""
        return self.occupied.shape  # type: ignore[return-value]

    @property
    def size_m(self) -> tuple[float, float]:
        """(width, height) of the bitmap in metres."""
        rows, cols = self.shape
        return cols * self.resolution, rows * self.resolution

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax) of the bitmap in world metres (its outer cell edges)."""
        rows, cols = self.shape
        half_w, half_h = cols * self.resolution / 2.0, rows * self.resolution / 2.0
        ox, oy = self.origin
        return ox - half_w, oy - half_h, ox + half_w, oy + half_h

    @property
    def free_area_m2(self) -> float:
        """Free area in m²."""
        return float((~self.occupied).sum()) * self.resolution ** 2

    def world_to_cell(self, xy) -> np.ndarray:
        """Integer (row, col) of world points (..., 2) in m; may lie outside the bitmap."""
        xy = np.asarray(xy, dtype=float)
        rows, cols = self.shape
        col = np.floor((xy[..., 0] - self.origin[0]) / self.resolution + cols / 2.0)
        row = np.floor(rows / 2.0 - (xy[..., 1] - self.origin[1]) / self.resolution)
        return np.stack([row, col], axis=-1).astype(np.int64)

    def cell_to_world(self, rc) -> np.ndarray:
        """World (x, y) in m of the centres of cells (..., 2) given as (row, col)."""
        rc = np.asarray(rc, dtype=float)
        rows, cols = self.shape
        x = self.origin[0] + (rc[..., 1] + 0.5 - cols / 2.0) * self.resolution
        y = self.origin[1] + (rows / 2.0 - rc[..., 0] - 0.5) * self.resolution
        return np.stack([x, y], axis=-1)

    def in_bounds(self, rc) -> np.ndarray:
        """True where cells (..., 2) lie inside the bitmap."""
        rc = np.asarray(rc)
        rows, cols = self.shape
        return (rc[..., 0] >= 0) & (rc[..., 0] < rows) & (rc[..., 1] >= 0) & (rc[..., 1] < cols)

    def is_free_at(self, xy) -> np.ndarray:
        """True where world points (..., 2) fall on free cells inside the bitmap."""
        rc = self.world_to_cell(xy)
        inside = self.in_bounds(rc)
        rows, cols = self.shape
        r = np.clip(rc[..., 0], 0, rows - 1)
        c = np.clip(rc[..., 1], 0, cols - 1)
        return inside & ~self.occupied[r, c]

    def replace(self, **changes: Any) -> World:
        """A copy with some fields changed."""
        return dataclasses.replace(self, **changes)


def check_occupancy(occupied: np.ndarray, source: str) -> None:
    """Raise InputError when a bitmap has no free cell."""
    if occupied.size == 0 or occupied.all():
        raise InputError("image has no free space", source)
