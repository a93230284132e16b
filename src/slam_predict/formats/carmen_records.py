"""Records of a CARMEN log: laser scans, odometry and the whole log (see :mod:`.carmen`)."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from slam_predict.errors import InputError


def flaser_angular_resolution(n_readings: int) -> float:
    """Beam spacing (rad) of an old-format FLASER scan of ``n_readings`` over a 180° field of view.

    An odd count includes both ends of the field (181 → 1°, 361 → 0.5°); an even count does not
    (180 → 1°, 360 → 0.5°), as CARMEN's front-laser messages do.
    """
    if n_readings <= 1:
        return math.pi
    spans = n_readings - 1 if n_readings % 2 == 1 else n_readings
    return math.pi / spans


@dataclass
class LaserScan:
    """One laser reading with the poses logged with it.

    ``pose`` is the laser pose of the line (FLASER ``x y theta``, ROBOTLASER1 ``laser_x..``) and
    ``odom_pose`` the robot's odometry pose (FLASER ``odom_*``, ROBOTLASER1 ``robot_*``), both
    (x m, y m, theta rad). ``kind`` is the message type it was read from / will be written as.
    """

    timestamp: float
    ranges: np.ndarray
    start_angle: float
    angular_resolution: float
    max_range: float
    pose: np.ndarray
    odom_pose: np.ndarray
    kind: str = "FLASER"
    logger_timestamp: float | None = None
    host: str = "slam_predict"
    fov: float | None = None
    remissions: np.ndarray = field(default_factory=lambda: np.zeros(0, np.float32))
    laser_type: int = 0
    accuracy: float = 0.0
    remission_mode: int = 0
    tv: float = 0.0
    rv: float = 0.0
    forward_safety_dist: float = 0.0
    side_safety_dist: float = 0.0
    turn_axis: float = 0.0

    def __post_init__(self):
        self.ranges = np.asarray(self.ranges, dtype=np.float32)
        self.pose = np.asarray(self.pose, dtype=float).reshape(3)
        self.odom_pose = np.asarray(self.odom_pose, dtype=float).reshape(3)
        self.remissions = np.asarray(self.remissions, dtype=np.float32)
        if self.fov is None:
            self.fov = self.angular_resolution * max(len(self.ranges) - 1, 0)

    @property
    def angles(self) -> np.ndarray:
        """Beam angles (rad) in the laser frame."""
        return self.start_angle + self.angular_resolution * np.arange(len(self.ranges))


@dataclass
class Odometry:
    """ODOM records as arrays: ``t`` (N,) s, ``poses`` (N, 3), velocities tv m/s, rv rad/s."""

    t: np.ndarray
    poses: np.ndarray
    tv: np.ndarray | None = None
    rv: np.ndarray | None = None
    accel: np.ndarray | None = None

    def __post_init__(self):
        self.t = np.asarray(self.t, dtype=float).reshape(-1)
        self.poses = np.asarray(self.poses, dtype=float).reshape(-1, 3)
        zeros = np.zeros(len(self.t))
        self.tv = zeros.copy() if self.tv is None else np.asarray(self.tv, dtype=float)
        self.rv = zeros.copy() if self.rv is None else np.asarray(self.rv, dtype=float)
        self.accel = zeros.copy() if self.accel is None else np.asarray(self.accel, dtype=float)

    def __len__(self) -> int:
        return len(self.t)


@dataclass
class CarmenLog:
    """Contents of a CARMEN log: PARAM values (strings), ODOM records and front-laser scans."""

    params: dict[str, str] = field(default_factory=dict)
    odometry: Odometry = field(default_factory=lambda: Odometry(np.zeros(0), np.zeros((0, 3))))
    scans: list[LaserScan] = field(default_factory=list)
    path: str | None = None

    @property
    def scan_times(self) -> np.ndarray:
        """Scan timestamps (s), shape (N,)."""
        return np.array([s.timestamp for s in self.scans], dtype=float)

    @property
    def scan_poses(self) -> np.ndarray:
        """Laser poses of the scans (FLASER ``x y theta``), shape (N, 3)."""
        return np.array([s.pose for s in self.scans], dtype=float).reshape(-1, 3)

    @property
    def scan_odom_poses(self) -> np.ndarray:
        """Odometry poses logged with the scans (FLASER ``odom_*``), shape (N, 3)."""
        return np.array([s.odom_pose for s in self.scans], dtype=float).reshape(-1, 3)

    def param_float(self, name: str, default: float | None = None) -> float | None:
        """A PARAM value as float, or ``default`` when absent."""
        if name not in self.params:
            return default
        try:
            return float(self.params[name])
        except ValueError as exc:
            raise InputError(f"PARAM {name} is not a number: {self.params[name]!r}",
                             self.path) from exc
