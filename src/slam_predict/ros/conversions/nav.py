"""Navigation messages: costmaps, plans, move_base goals and frontier markers ↔ ROS.

* Costmaps are published as ``nav_msgs/OccupancyGrid`` with costmap_2d's translation table
  (Costmap2DPublisher): 0 → 0, 253 → 99, 254 → 100, 255 → −1, 1..252 → 1 + 97·(c − 1)/251.
* Plans (poses (n, 3) x, y, yaw) ↔ ``nav_msgs/Path``.
* Goals (x, y, yaw) ↔ ``move_base_msgs/MoveBaseGoal`` / ``geometry_msgs/PoseStamped``, with
  move_base's quaternion check (finite, non-zero length, rotation about z only).
* Frontiers ↔ ``visualization_msgs/MarkerArray`` as explore_lite draws them: one POINTS marker
  per frontier (its cells) and one SPHERE at its goal point, ids 2k and 2k + 1.
"""
from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from geometry_msgs.msg import Point, Point32, PolygonStamped, PoseStamped
from move_base_msgs.msg import MoveBaseGoal
from nav_msgs.msg import Path
from visualization_msgs.msg import Marker, MarkerArray

from slam_predict.nav.costmap import Costmap
from slam_predict.ros.conversions.geometry import pose_from_ros, pose_to_ros, time_to_ros
from slam_predict.ros.conversions.slam import grid_from_ros, grid_to_ros
from slam_predict.slam import OccupancyGrid

_TO_GRID = np.zeros(256, np.int8)
_TO_GRID[1:253] = (1 + (97 * (np.arange(1, 253) - 1)) // 251).astype(np.int8)
_TO_GRID[253], _TO_GRID[254], _TO_GRID[255] = 99, 100, -1


def costmap_values(costs: np.ndarray) -> np.ndarray:
    """int8 OccupancyGrid values of uint8 costs (costmap_2d's publisher table)."""
    return _TO_GRID[np.asarray(costs, dtype=np.uint8)]


def costmap_to_ros(costmap: Costmap, frame_id: str, stamp: float = 0.0):
    """``nav_msgs/OccupancyGrid`` of a costmap (numpy_msg flavour, fast for big maps)."""
    grid = OccupancyGrid(costmap_values(costmap.costs), costmap.resolution, costmap.origin)
    return grid_to_ros(grid, frame_id, stamp)


def costmap_from_ros(msg) -> Costmap:
    """A Costmap from a published costmap grid; each value maps back to the smallest cost
    that publishes as it (exact for 0, 253, 254 and 255)."""
    grid = grid_from_ros(msg)
    inverse = np.zeros(256, np.uint8)
    for cost in range(255, -1, -1):
        inverse[int(_TO_GRID[cost]) & 0xFF] = cost
    costs = inverse[grid.data.astype(np.int16) & 0xFF]
    return Costmap(costs.astype(np.uint8), grid.origin, grid.resolution)


def plan_to_ros(poses: np.ndarray, frame_id: str, stamp: float = 0.0) -> Path:
    """``nav_msgs/Path`` of poses (n, 3)."""
    msg = Path()
    msg.header.frame_id = frame_id
    msg.header.stamp = time_to_ros(stamp)
    for pose in np.asarray(poses, dtype=float).reshape(-1, 3):
        stamped = PoseStamped()
        stamped.header = msg.header
        stamped.pose = pose_to_ros(pose)
        msg.poses.append(stamped)
    return msg


def polygon_to_ros(polygon: np.ndarray, pose: Sequence[float], frame_id: str,
                   stamp: float = 0.0) -> PolygonStamped:
    """``geometry_msgs/PolygonStamped`` of a robot-frame polygon (k, 2) m placed at ``pose``
    (x, y, yaw) of ``frame_id`` (costmap_2d's published footprint)."""
    from slam_predict.geometry import transform_points

    msg = PolygonStamped()
    msg.header.frame_id = frame_id
    msg.header.stamp = time_to_ros(stamp)
    points = transform_points(np.asarray(pose, dtype=float), np.asarray(polygon, dtype=float))
    msg.polygon.points = [Point32(float(x), float(y), 0.0) for x, y in points.reshape(-1, 2)]
    return msg


def polygon_from_ros(msg: PolygonStamped) -> np.ndarray:
    """The polygon's vertices (k, 2) m in the message's frame."""
    return np.array([[p.x, p.y] for p in msg.polygon.points], dtype=float).reshape(-1, 2)


def plan_from_ros(msg: Path) -> np.ndarray:
    """Poses (n, 3) of a ``nav_msgs/Path``."""
    if not msg.poses:
        return np.empty((0, 3))
    return np.array([pose_from_ros(p.pose) for p in msg.poses])


def quaternion_valid(q) -> bool:
    """move_base's isQuaternionValid: finite, length > 1e-6, rotation about z only."""
    values = (q.x, q.y, q.z, q.w)
    if not all(math.isfinite(v) for v in values):
        return False
    norm = math.sqrt(sum(v * v for v in values))
    if norm < 1e-6:
        return False
    x, y, z, w = (v / norm for v in values)
    # the rotated z axis must stay (almost) vertical
    zz = 1.0 - 2.0 * (x * x + y * y)
    return abs(zz - 1.0) <= 1e-3


def pose_stamped_to_ros(target: Sequence[float], frame_id: str, stamp: float = 0.0) -> PoseStamped:
    """``geometry_msgs/PoseStamped`` of (x, y, yaw)."""
    msg = PoseStamped()
    msg.header.frame_id = frame_id
    msg.header.stamp = time_to_ros(stamp)
    msg.pose = pose_to_ros(target)
    return msg


def pose_stamped_from_ros(msg: PoseStamped) -> tuple[np.ndarray, str] | None:
    """((x, y, yaw), frame_id), or None for an invalid quaternion."""
    if not quaternion_valid(msg.pose.orientation):
        return None
    return pose_from_ros(msg.pose), msg.header.frame_id


def goal_to_ros(target: Sequence[float], frame_id: str = "map", stamp: float = 0.0) -> MoveBaseGoal:
    """``move_base_msgs/MoveBaseGoal`` for (x, y, yaw)."""
    goal = MoveBaseGoal()
    goal.target_pose = pose_stamped_to_ros(target, frame_id, stamp)
    return goal


def goal_from_ros(goal: MoveBaseGoal) -> tuple[np.ndarray, str] | None:
    """((x, y, yaw), frame_id) of a MoveBaseGoal, or None for an invalid quaternion."""
    return pose_stamped_from_ros(goal.target_pose)


def frontiers_to_ros(frontiers, frame_id: str, stamp: float = 0.0,
                     blacklisted: Sequence[bool] = ()) -> MarkerArray:
    """MarkerArray of frontiers (cells as POINTS, the goal as a SPHERE); the first message
    of a new set starts with a DELETEALL marker so vanished frontiers disappear."""
    out = MarkerArray()
    clear = Marker()
    clear.header.frame_id = frame_id
    clear.action = Marker.DELETEALL
    out.markers.append(clear)
    for k, frontier in enumerate(frontiers):
        red = bool(blacklisted[k]) if k < len(blacklisted) else False
        points = _marker(frame_id, stamp, 2 * k, Marker.POINTS, red)
        points.scale.x = points.scale.y = 0.05
        points.points = [Point(float(x), float(y), 0.0) for x, y in frontier.cells]
        sphere = _marker(frame_id, stamp, 2 * k + 1, Marker.SPHERE, red)
        sphere.pose.position.x, sphere.pose.position.y = (float(v) for v in frontier.goal)
        sphere.pose.orientation.w = 1.0
        sphere.scale.x = sphere.scale.y = sphere.scale.z = 0.2
        out.markers.extend([points, sphere])
    return out


def frontiers_from_ros(msg: MarkerArray) -> list[tuple[np.ndarray, np.ndarray]]:
    """[(cells (n, 2), goal (2,)), ...] of a frontier MarkerArray, in id order."""
    points = {m.id: m for m in msg.markers if m.type == Marker.POINTS}
    spheres = {m.id: m for m in msg.markers if m.type == Marker.SPHERE}
    out = []
    for marker_id in sorted(points):
        cells = np.array([(p.x, p.y) for p in points[marker_id].points]).reshape(-1, 2)
        sphere = spheres.get(marker_id + 1)
        goal = np.array([sphere.pose.position.x, sphere.pose.position.y]) if sphere else None
        out.append((cells, goal))
    return out


def _marker(frame_id: str, stamp: float, marker_id: int, kind: int, red: bool) -> Marker:
    marker = Marker()
    marker.header.frame_id = frame_id
    marker.header.stamp = time_to_ros(stamp)
    marker.ns = "frontiers"
    marker.id = marker_id
    marker.type = kind
    marker.action = Marker.ADD
    marker.color.a = 1.0
    marker.color.r, marker.color.g, marker.color.b = (1.0, 0.0, 0.0) if red else (0.0, 0.0, 1.0)
    return marker
