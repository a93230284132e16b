"""SLAM back-ends behind one small interface, registered by name (the YAML ``type:`` field).

A back-end is fed, scan by scan, the robot's odometry pose and the laser ranges::

    slam = create("gmapping", params=..., laser=LaserGeometry(...), rng=np.random.default_rng(1))
    for odom_pose, ranges, t in stream:
        pose = slam.update(odom_pose, ranges, t)   # map-frame robot pose when processed, else None
    grid = slam.map()                               # OccupancyGrid
    slam.map_to_odom()                              # (x, y, yaw) of the odom frame in the map frame

Poses are (x m, y m, yaw rad) of the robot base; ranges in m, times in s.
"""
from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import Callable, Dict, Optional, Tuple, Union

import numpy as np

from slam_predict.errors import InputError, did_you_mean


@dataclass
class LaserGeometry:
    """A planar laser: beam angles (rad, in the laser frame, increasing), its pose in the robot
    base frame (x m, y m, yaw rad) and the sensor's maximum range (m; NaN if unknown)."""

    angles: np.ndarray
    pose_in_base: Tuple[float, float, float] = (0.0, 0.0, 0.0)
    range_max: float = float("nan")

    def __post_init__(self):
        self.angles = np.asarray(self.angles, dtype=float).reshape(-1)
        self.pose_in_base = tuple(float(v) for v in self.pose_in_base)

    @property
    def beams(self) -> int:
        """Number of beams."""
        return len(self.angles)


@dataclass
class OccupancyGrid:
    """A ROS-style occupancy grid: ``data`` (height, width) int8 with −1 unknown, 0 free, 100
    occupied; row 0 is the lowest y; ``origin`` (x, y) m is the world position of cell (0, 0) as
    the producer defines it; ``resolution`` m/cell."""

    data: np.ndarray
    resolution: float
    origin: Tuple[float, float]

    @property
    def width(self) -> int:
        """Number of columns (cells along x)."""
        return int(self.data.shape[1])

    @property
    def height(self) -> int:
        """Number of rows (cells along y)."""
        return int(self.data.shape[0])


class SlamBackend:
    """Interface of a SLAM back-end (see the module docstring)."""

    name = "abstract"

    def update(self, odom_pose, scan_ranges, t: float) -> Optional[np.ndarray]:
        """Feed one scan with the odometry pose at its time; the new map-frame pose if the scan
        was processed, else None."""
        raise NotImplementedError

    def map(self) -> OccupancyGrid:
        """The current map."""
        raise NotImplementedError

    def pose(self) -> np.ndarray:
        """The current best robot pose in the map frame."""
        raise NotImplementedError

    def map_to_odom(self) -> np.ndarray:
        """The odom frame's pose in the map frame."""
        raise NotImplementedError


# name -> factory, or "module:attribute" resolved on first use (keeps imports light)
_REGISTRY: Dict[str, Union[str, Callable[..., SlamBackend]]] = {
    "gmapping": "slam_predict.slam.gmapping.filter:GMapping",
}


def register(name: str, factory: Union[str, Callable[..., SlamBackend]]) -> None:
    """Register a back-end factory under ``name``; duplicate names are refused."""
    if name in _REGISTRY:
        raise ValueError(f"SLAM back-end '{name}' is already registered")
    _REGISTRY[name] = factory


def available() -> Tuple[str, ...]:
    """Registered back-end names."""
    return tuple(sorted(_REGISTRY))


def create(name: str, **kwargs) -> SlamBackend:
    """Instantiate the back-end registered as ``name`` with ``kwargs``."""
    if name not in _REGISTRY:
        raise InputError(f"unknown SLAM type '{name}'" + did_you_mean(name, _REGISTRY))
    factory = _REGISTRY[name]
    if isinstance(factory, str):
        module, attr = factory.split(":")
        factory = getattr(importlib.import_module(module), attr)
        _REGISTRY[name] = factory
    return factory(**kwargs)
