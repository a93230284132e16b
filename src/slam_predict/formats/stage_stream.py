"""What stage_ros publishes for one simulator step, without ROS (ros_interfaces.md §1.5).

Per step, stamped with the step's sim time rounded to the nanosecond (as a ``ros::Time``):
tf ``odom → base_footprint`` (odometry pose), ``base_footprint → base_link`` (identity),
``base_link → base_laser_link`` (laser mounting pose, z = ``laser_z``); ``odom``
(nav_msgs/Odometry, frame ``odom``, child ``base_footprint``, twist = executed velocity, body
frame); ``base_pose_ground_truth`` (world pose, twist = finite difference over the step, world
frame); ``base_scan`` (sensor_msgs/LaserScan, frame ``base_laser_link``) when a scan was taken.

LaserScan fields are float32 in the message, so :class:`LaserDescription` holds them rounded to
float32 (angle_min = −fov/2, angle_increment = fov/(samples−1), time_increment = scan_time = 0),
and the ranges are the simulator's float32 readings. Intensities are 1 for a hit, 0 for no
return (stage_ros: the hit model's ranger_return).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from slam_predict.geometry import wrap_angle, yaw_to_quaternion

ODOM_FRAME, FOOTPRINT_FRAME, BASE_FRAME, LASER_FRAME = (
    "odom", "base_footprint", "base_link", "base_laser_link")
SCAN_TOPIC, ODOM_TOPIC, TRUTH_TOPIC = "/base_scan", "/odom", "/base_pose_ground_truth"


def ros_time(t: float) -> tuple[int, int]:
    """Seconds → (sec, nsec) of a ros::Time, rounded to the nearest nanosecond."""
    total = int(round(float(t) * 1e9))
    return total // 1_000_000_000, total % 1_000_000_000


def stamp_seconds(sec: int, nsec: int) -> float:
    """(sec, nsec) → seconds, computed as every reader here does (``sec + nsec·1e-9``)."""
    return sec + nsec * 1e-9


def _f32(value: float) -> float:
    return float(np.float32(value))


@dataclass(frozen=True)
class Transform:
    """One tf link: ``child`` in ``parent``; translation (x, y, z) m, rotation (qx, qy, qz, qw)."""

    parent: str
    child: str
    translation: tuple[float, float, float]
    rotation: tuple[float, float, float, float]

    @property
    def value(self) -> np.ndarray:
        """(tx, ty, tz, qx, qy, qz, qw) as a tf reader stores it."""
        return np.array([*self.translation, *self.rotation], dtype=float)


def planar_transform(parent: str, child: str, pose, z: float = 0.0) -> Transform:
    """The tf link of a planar pose (x m, y m, yaw rad) with a yaw-only quaternion."""
    q = yaw_to_quaternion(float(pose[2]))
    return Transform(parent, child, (float(pose[0]), float(pose[1]), float(z)),
                     tuple(float(v) for v in q))


@dataclass(frozen=True)
class LaserDescription:
    """The constant part of the published LaserScan (float32-exact values) and the laser's tf
    link ``base_link → base_laser_link``."""

    angle_min: float
    angle_max: float
    angle_increment: float
    range_min: float
    range_max: float
    beams: int
    mount: Transform
    time_increment: float = 0.0
    scan_time: float = 0.0
    frame_id: str = LASER_FRAME

    @classmethod
    def of(cls, laser_spec, laser_pose, laser_z: float = 0.0) -> LaserDescription:
        """From a :class:`~slam_predict.world.model.LaserSpec` and the laser pose on the robot."""
        fov, samples = float(laser_spec.fov), int(laser_spec.samples)
        increment = fov / (samples - 1) if samples > 1 else 0.0
        return cls(angle_min=_f32(-fov / 2.0), angle_max=_f32(fov / 2.0),
                   angle_increment=_f32(increment), range_min=_f32(laser_spec.range_min),
                   range_max=_f32(laser_spec.range_max), beams=samples,
                   mount=planar_transform(BASE_FRAME, LASER_FRAME, laser_pose, laser_z))

    def intensities(self, ranges: np.ndarray) -> np.ndarray:
        """1 where a beam hit something (reading below range_max), else 0 (float32)."""
        return (np.asarray(ranges) < np.float32(self.range_max)).astype(np.float32)


@dataclass
class StepMessages:
    """Everything stage_ros publishes at one step (see the module docstring)."""

    sec: int
    nsec: int
    transforms: list[Transform]
    odom_pose: np.ndarray                      # (x, y, yaw) in the odom frame
    odom_twist: tuple[float, float, float]     # (vx, vy, ω), body frame
    true_pose: np.ndarray                      # (x, y, yaw) in the world frame
    true_twist: tuple[float, float, float]     # (vx, vy, ω), world frame
    ranges: np.ndarray | None = None        # float32 m, when a scan was taken

    @property
    def t(self) -> float:
        """The stamp in seconds, as a reader of the messages computes it."""
        return stamp_seconds(self.sec, self.nsec)


class StagePublisher:
    """Turns simulator states into :class:`StepMessages`; keeps the previous true pose for the
    ground-truth twist, so it must see every step."""

    def __init__(self, laser: LaserDescription, dt: float, start_pose):
        self.laser = laser
        self.dt = float(dt)
        self._prev_true = np.asarray(start_pose, dtype=float).copy()

    @classmethod
    def of(cls, sim, laser_z: float = 0.0) -> StagePublisher:
        """For a :class:`~slam_predict.sim.Simulator` (its laser, step and start pose)."""
        return cls(LaserDescription.of(sim.laser, sim.laser_pose, laser_z), sim.dt,
                   sim.world.start_pose)

    def messages(self, state) -> StepMessages:
        """The messages of one :class:`~slam_predict.sim.simulator.SimState`."""
        sec, nsec = ros_time(state.t)
        prev, now = self._prev_true, np.asarray(state.true_pose, dtype=float)
        self._prev_true = now.copy()
        true_twist = ((now[0] - prev[0]) / self.dt, (now[1] - prev[1]) / self.dt,
                      float(wrap_angle(now[2] - prev[2])) / self.dt)
        v, w = state.velocity
        return StepMessages(sec, nsec, scan_transforms(self.laser, state.odom_pose),
                            np.array(state.odom_pose, dtype=float), (float(v), 0.0, float(w)),
                            now.copy(), true_twist,
                            None if state.scan is None else np.asarray(state.scan, np.float32))


def scan_transforms(laser: LaserDescription, odom_pose) -> list[Transform]:
    """The three tf links published with every step, for odometry pose ``odom_pose``."""
    return [planar_transform(ODOM_FRAME, FOOTPRINT_FRAME, odom_pose),
            planar_transform(FOOTPRINT_FRAME, BASE_FRAME, (0.0, 0.0, 0.0)),
            laser.mount]
