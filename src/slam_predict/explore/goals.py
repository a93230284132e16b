"""The explorer's side of move_base: goal status codes, the goal client it drives, the goal it
tracks, the heading it faces and the log of goal outcomes (shared by every strategy of
:mod:`slam_predict.explore.explorer` and :mod:`slam_predict.explore.thesis_strategy`)."""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np

SUCCEEDED, ABORTED, PREEMPTED = 3, 4, 2  # actionlib_msgs/GoalStatus
HEADING_UNDEFINED_M = 0.1   # m: a goal point this close to the robot gives no heading


def facing(point, robot_pose, at_start: bool = False) -> float:
    """Heading (rad) from the robot's pose (x, y, yaw) to ``point`` (x, y); ``at_start``,
    backwards (yaw + π) when the point is within :data:`HEADING_UNDEFINED_M` of the robot."""
    dx, dy = point[0] - robot_pose[0], point[1] - robot_pose[1]
    if at_start and math.hypot(dx, dy) < HEADING_UNDEFINED_M:
        return math.atan2(math.sin(robot_pose[2] + math.pi), math.cos(robot_pose[2] + math.pi))
    return math.atan2(dy, dx)


class GoalClient(Protocol):
    """What the explorer needs from move_base (in-process navigator or actionlib client)."""

    def send_goal(self, target: tuple[float, float, float], t: float) -> None: ...

    def cancel(self, t: float) -> None: ...

    def status(self) -> int | None: ...

    def plan_length(self) -> float | None: ...


@dataclass
class Goal:
    """The explorer's current goal."""

    target: tuple[float, float, float]
    t_sent: float
    frontier_point: np.ndarray
    frontier_size: int
    min_distance: float
    time_limit: float | None = None
    last_progress: float = 0.0
    look_around: bool = False
    in_place: bool = False


@dataclass
class ExploreLog:
    """What happened: one dict per goal outcome, and the stop reason."""

    goals: list[dict[str, Any]] = field(default_factory=list)
    stop_reason: str | None = None
    t_stop: float | None = None

    def counts(self) -> dict[str, int]:
        """Goal outcomes by kind."""
        out: dict[str, int] = {}
        for g in self.goals:
            out[g["outcome"]] = out.get(g["outcome"], 0) + 1
        return out
