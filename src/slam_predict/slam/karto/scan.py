"""Karto's LaserRangeFinder and LocalizedRangeScan as slam_toolbox fills them: a scan's
odometric and corrected robot poses, its sensor pose and its point readings (m, rad)."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

TOLERANCE = 1e-6   # KT_TOLERANCE
ORIGIN = (0.0, 0.0, 0.0)


def normalize_angle(angle: float) -> float:
    """Karto's math::NormalizeAngle: the angle moved by whole turns into [−π, π] (rad)."""
    two_pi = 2.0 * math.pi
    while angle < -math.pi:
        angle += int(angle / -two_pi) * two_pi if angle < -two_pi else two_pi
    while angle > math.pi:
        angle -= int(angle / two_pi) * two_pi if angle > two_pi else two_pi
    return angle


def compose(a, b) -> np.ndarray:
    """Pose b (x, y, yaw) expressed in frame a, in a's parent frame."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return np.array([a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1],
                     normalize_angle(a[2] + b[2])])


def relative(a, b) -> np.ndarray:
    """Pose b in the frame of pose a (a⁻¹ ∘ b)."""
    c, s = math.cos(a[2]), math.sin(a[2])
    dx, dy = b[0] - a[0], b[1] - a[1]
    return np.array([c * dx + s * dy, -s * dx + c * dy, normalize_angle(b[2] - a[2])])


def transform_pose(frame_from, frame_to, pose) -> np.ndarray:
    """Karto's ``Transform(frame_from, frame_to).TransformPose(pose)`` in its arithmetic
    (FromAxisAngle rotation rows, translation frame_to − R·frame_from, heading added then
    normalised): the pose moved by the rigid motion taking frame_from onto frame_to."""
    turn = frame_to[2] - frame_from[2]
    c, s = math.cos(turn), math.sin(turn)
    tx, ty = frame_to[0], frame_to[1]
    if frame_from[0] != 0.0 or frame_from[1] != 0.0:
        tx = frame_to[0] - (c * frame_from[0] + -s * frame_from[1] + 0.0 * frame_from[2])
        ty = frame_to[1] - (s * frame_from[0] + c * frame_from[1] + 0.0 * frame_from[2])
    return np.array([tx + (c * pose[0] + -s * pose[1] + 0.0 * pose[2]),
                     ty + (s * pose[0] + c * pose[1] + 0.0 * pose[2]),
                     normalize_angle(pose[2] + turn)])


@dataclass(frozen=True)
class RangeFinder:
    """The laser as slam_toolbox describes it to Karto: mounting pose in the base frame, first
    beam angle and angular step (rad), minimum and maximum range and the range threshold
    (``max_laser_range`` capped at the sensor's maximum) (m)."""

    offset: tuple[float, float, float]
    minimum_angle: float
    angular_resolution: float
    minimum_range: float
    maximum_range: float
    range_threshold: float
    beams: int


@dataclass
class LocalizedScan:
    """One scan given to the Mapper: input index, time (s), odometric and corrected robot poses,
    range readings (m); ``unique_id`` is set when the Mapper keeps it."""

    laser: RangeFinder
    input_index: int
    time: float
    odometric_pose: np.ndarray
    ranges: np.ndarray
    corrected_pose: np.ndarray = field(default=None)
    unique_id: int = -1

    def __post_init__(self):
        self.odometric_pose = np.asarray(self.odometric_pose, float)
        if self.corrected_pose is None:
            self.corrected_pose = self.odometric_pose.copy()
        self._update()

    def sensor_at(self, robot_pose) -> np.ndarray:
        """The laser pose when the robot is at ``robot_pose``."""
        return transform_pose(ORIGIN, robot_pose, self.laser.offset)

    @property
    def sensor_pose(self) -> np.ndarray:
        """Laser pose of the corrected robot pose."""
        return self.sensor_at(self.corrected_pose)

    def set_corrected_pose(self, pose) -> None:
        """New corrected robot pose; the point readings follow."""
        self.corrected_pose = np.asarray(pose, float)
        self._update()

    def corrected_at(self, sensor_pose) -> np.ndarray:
        """LocalizedRangeScan::GetCorrectedAt: the robot pose whose laser is at ``sensor_pose``."""
        ox, oy, oh = self.laser.offset
        length = math.hypot(ox, oy)
        heading = normalize_angle(sensor_pose[2])
        along = heading + math.atan2(oy, ox) - oh
        return np.array([sensor_pose[0] - length * math.cos(along),
                         sensor_pose[1] - length * math.sin(along),
                         normalize_angle(sensor_pose[2] - oh)])

    def set_sensor_pose(self, sensor_pose) -> None:
        """LocalizedRangeScan::SetSensorPose: move the robot so its laser is at ``sensor_pose``."""
        self.set_corrected_pose(self.corrected_at(sensor_pose))

    def _update(self) -> None:
        laser = self.laser
        sx, sy, sh = self.sensor_pose
        angles = sh + laser.minimum_angle + np.arange(laser.beams) * laser.angular_resolution
        with np.errstate(invalid="ignore"):
            self.points = np.column_stack((sx + self.ranges * np.cos(angles),
                                           sy + self.ranges * np.sin(angles)))
            self.in_range = ((self.ranges >= laser.minimum_range)
                             & (self.ranges <= laser.range_threshold))
        self.finite = np.isfinite(self.ranges)
        filtered = self.points[self.in_range]
        self.barycenter = filtered.mean(axis=0) if len(filtered) else np.array([sx, sy])
        box = np.vstack((filtered, [[sx, sy]]))
        self.box_min, self.box_max = box.min(axis=0), box.max(axis=0)
