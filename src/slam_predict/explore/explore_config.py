"""The explorer's parameters: explore_lite's names plus the thesis' goal time limit and the
extensions the module :mod:`slam_predict.explore.explorer` describes (m, s, Hz)."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar

from slam_predict.config import AT_LEAST_ONE, NON_NEGATIVE, POSITIVE, Range
from slam_predict.explore.thesis_config import ThesisExploreConfig

STRATEGIES = ("thesis", "nearest", "explore_lite")


@dataclass
class ExploreConfig:
    """explore_lite's parameters plus the thesis' goal timeout (m, s, Hz)."""

    strategy: str = "nearest"
    robot_base_frame: str = "base_link"
    costmap_topic: str = "map"
    costmap_updates_topic: str = "map_updates"
    visualize: bool = True
    planner_frequency: float = 1.0
    progress_timeout: float = 30.0
    potential_scale: float = 3.0
    orientation_scale: float = 0.0
    gain_scale: float = 1.0
    transform_tolerance: float = 0.3
    min_frontier_size: float = 0.75
    goal_timeout_factor: float = 2.0
    goal_timeout_offset: float = 30.0
    max_vel_x: float = 0.85
    tie_tolerance: float = 0.05
    blacklist_radius: float = 0.5
    goal_frontier_radius: float = 1.0
    max_goal_attempts: int = 3
    goal_yaw: str = "approach"
    near_frontier_distance: float = 1.0
    goal_clearance: float = 0.5
    blacklist_retries: int = 0
    min_unknown_width: float = 0.0
    reachable_frontiers: bool = False
    reachable_first: bool = False
    thesis: ThesisExploreConfig = field(default_factory=ThesisExploreConfig)
    HASH_OMIT_IF: ClassVar[dict[str, Any]] = {"reachable_frontiers": False,   # added later
                                              "reachable_first": False}
    RANGES: ClassVar[dict[str, Range]] = {
        "planner_frequency": POSITIVE, "max_vel_x": POSITIVE, "goal_timeout_factor": POSITIVE,
        "max_goal_attempts": AT_LEAST_ONE, **{name: NON_NEGATIVE for name in (
            "progress_timeout", "potential_scale", "orientation_scale", "gain_scale",
            "transform_tolerance", "min_frontier_size", "goal_timeout_offset", "tie_tolerance",
            "blacklist_radius", "goal_frontier_radius", "near_frontier_distance",
            "goal_clearance", "blacklist_retries", "min_unknown_width")}}

    def __post_init__(self) -> None:
        if self.strategy not in STRATEGIES:
            raise ValueError(f"strategy must be one of {', '.join(STRATEGIES)}, got "
                             f"'{self.strategy}'")
        if self.goal_yaw not in ("approach", "zero"):
            raise ValueError("goal_yaw must be 'approach' or 'zero'")
        if not (self.planner_frequency > 0 and self.max_vel_x > 0):
            raise ValueError("planner_frequency and max_vel_x must be > 0")
        if self.blacklist_retries < 0:
            raise ValueError("blacklist_retries must be >= 0")
        if self.min_unknown_width < 0:
            raise ValueError("min_unknown_width must be >= 0")
