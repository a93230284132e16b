"""The explorer's side of move_base: goal status codes, the goal client it drives, the goal it
tracks and the log of goal outcomes (shared by every strategy of
:mod:`slam_predict.explore.explorer` and :mod:`slam_predict.explore.thesis_strategy`)."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np

SUCCEEDED, ABORTED, PREEMPTED = 3, 4, 2  # actionlib_msgs/GoalStatus


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
