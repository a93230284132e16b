"""Planar poses, velocities, odometry, TF and clock ↔ ROS messages.

Times are float seconds of sim time on our side, ``rospy.Time`` on the message side. Poses are
(x, y, yaw) in m, m, rad; messages carry z = 0 and a yaw-only quaternion. Velocities are body
frame (vx m/s, vy m/s, ω rad/s).
"""
from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np
import rospy
from geometry_msgs.msg import Pose, TransformStamped, Twist
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock

from slam_predict.geometry import quaternion_to_yaw, yaw_to_quaternion


def time_to_ros(t: float) -> rospy.Time:
    """Seconds → rospy.Time, rounded to the nearest nanosecond."""
    total = int(round(float(t) * 1e9))
    return rospy.Time(total // 1_000_000_000, total % 1_000_000_000)


def time_from_ros(stamp) -> float:
    """rospy.Time (or genpy Time) → seconds."""
    return stamp.secs + stamp.nsecs * 1e-9


def pose_to_ros(pose: Sequence[float]) -> Pose:
    """(x, y, yaw) → geometry_msgs/Pose (z = 0)."""
    msg = Pose()
    msg.position.x, msg.position.y = float(pose[0]), float(pose[1])
    qx, qy, qz, qw = yaw_to_quaternion(float(pose[2]))
    msg.orientation.x, msg.orientation.y = float(qx), float(qy)
    msg.orientation.z, msg.orientation.w = float(qz), float(qw)
    return msg


def pose_from_ros(msg: Pose) -> np.ndarray:
    """geometry_msgs/Pose → (x, y, yaw); the quaternion is projected to the plane."""
    q = msg.orientation
    return np.array([msg.position.x, msg.position.y,
                     float(quaternion_to_yaw(q.x, q.y, q.z, q.w))])


def twist_to_ros(velocity: Sequence[float]) -> Twist:
    """(vx, ω) or (vx, vy, ω) → geometry_msgs/Twist."""
    vx, vy, w = _velocity3(velocity)
    msg = Twist()
    msg.linear.x, msg.linear.y, msg.angular.z = vx, vy, w
    return msg


def twist_from_ros(msg: Twist) -> tuple[float, float, float]:
    """geometry_msgs/Twist → (vx, vy, ω) (the planar part, as stageros' SetSpeed)."""
    return float(msg.linear.x), float(msg.linear.y), float(msg.angular.z)


def _velocity3(velocity: Sequence[float]) -> tuple[float, float, float]:
    if len(velocity) == 2:
        return float(velocity[0]), 0.0, float(velocity[1])
    return float(velocity[0]), float(velocity[1]), float(velocity[2])


class OdometryData(NamedTuple):
    """Our side of a nav_msgs/Odometry: stamp s, frames, pose (x, y, yaw), twist (vx, vy, ω)."""

    stamp: float
    frame_id: str
    child_frame_id: str
    pose: np.ndarray
    twist: tuple[float, float, float]


def odometry_to_ros(pose: Sequence[float], velocity: Sequence[float], stamp: float,
                    frame_id: str = "odom", child_frame_id: str = "base_footprint") -> Odometry:
    """nav_msgs/Odometry with zero covariances (as stageros)."""
    msg = Odometry()
    msg.header.stamp = time_to_ros(stamp)
    msg.header.frame_id = frame_id
    msg.child_frame_id = child_frame_id
    msg.pose.pose = pose_to_ros(pose)
    msg.twist.twist = twist_to_ros(velocity)
    return msg


def odometry_from_ros(msg: Odometry) -> OdometryData:
    """nav_msgs/Odometry → :class:`OdometryData`."""
    return OdometryData(time_from_ros(msg.header.stamp), msg.header.frame_id,
                        msg.child_frame_id, pose_from_ros(msg.pose.pose),
                        twist_from_ros(msg.twist.twist))


class TransformData(NamedTuple):
    """Our side of a TransformStamped: stamp s, parent, child, pose (x, y, yaw), z m."""

    stamp: float
    parent: str
    child: str
    pose: np.ndarray
    z: float = 0.0


def transform_to_ros(pose: Sequence[float], stamp: float, parent: str, child: str,
                     z: float = 0.0) -> TransformStamped:
    """A planar transform (child's pose in parent) as geometry_msgs/TransformStamped."""
    msg = TransformStamped()
    msg.header.stamp = time_to_ros(stamp)
    msg.header.frame_id = parent
    msg.child_frame_id = child
    msg.transform.translation.x = float(pose[0])
    msg.transform.translation.y = float(pose[1])
    msg.transform.translation.z = float(z)
    qx, qy, qz, qw = yaw_to_quaternion(float(pose[2]))
    rot = msg.transform.rotation
    rot.x, rot.y, rot.z, rot.w = float(qx), float(qy), float(qz), float(qw)
    return msg


def transform_from_ros(msg: TransformStamped) -> TransformData:
    """geometry_msgs/TransformStamped → :class:`TransformData`."""
    tr, q = msg.transform.translation, msg.transform.rotation
    yaw = float(quaternion_to_yaw(q.x, q.y, q.z, q.w))
    return TransformData(time_from_ros(msg.header.stamp), msg.header.frame_id,
                         msg.child_frame_id, np.array([tr.x, tr.y, yaw]), float(tr.z))


def clock_to_ros(t: float) -> Clock:
    """Sim time (s) → rosgraph_msgs/Clock."""
    return Clock(clock=time_to_ros(t))


def clock_from_ros(msg: Clock) -> float:
    """rosgraph_msgs/Clock → s."""
    return time_from_ros(msg.clock)

