"""Parameters of the ``thesis`` strategy: the modified aau ``explorer`` the seed study ran
(values from its explorer.cpp, ExplorationPlanner.cpp and param/pioneer3at_*costmap*.yaml;
names follow the package where it has one). Units: s, m, cells, costmap cost values."""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from slam_predict.config import NON_NEGATIVE, Range


@dataclass
class ThesisExploreConfig:
    """The aau explorer's timing, costmap, frontier and back-off constants."""

    start_delay: float = 15.0              # s: explore()'s 5 s sleep + the first round's 10 s
    selection_pause: float = 2.0           # s: the two 1 s sleeps before each selection
    wait_for_planner_result: float = 3.0   # s: first waitForResult of move_robot
    poll_period: float = 0.5               # s: goal state polling after that
    max_time_before_goal_abortion: float = 90.0   # s: then the goal is cancelled (failed)
    auction_wait: float = 3.0              # s: the single-robot auction's wait for bids
    auction_jitter: float = 2.0            # s: plus a uniform random wait up to this
    costmap_resolution: float = 0.1        # m: the explorer's global costmap
    inscribed_radius: float = 0.2          # m: the thesis' 0.4 m square costmap footprint
    inflation_radius: float = 2.25         # m
    cost_scaling_factor: float = 7.5       # 1/m
    max_goal_range: float = 0.2            # m: MAX_GOAL_RANGE (per axis)
    cluster_join_dist: float = 1.0         # m: MAX_NEIGHBOR_DIST (per axis)
    cluster_merge_dist: float = 0.8        # m: CLUSTER_MERGING_DIST (per axis)
    seen_check_cells: int = 6              # clearSeenFrontiers' reach along the axes
    backoff_search_cells: int = 40         # smartGoalBackoff's reach along the axes
    backoff_inner_cells: int = 5           # INNER_DISTANCE
    acceptable_goal_cost: int = 50         # ACCEPTABLE_GOAL_COST
    turn_yaw: float = 45.0                 # rad: turn_robot's goal yaw (45, used as radians)
    return_home: bool = True               # drive back to the start when no goal is left
    home_attempts: int = 5
    max_idle_turns: int = 10               # extension: turns in a row with no valid point
    # every number but turn_yaw (a yaw, any sign) is >= 0; __post_init__ adds the > 0 / >= 1 rules
    RANGES: ClassVar[dict[str, Range]] = {name: NON_NEGATIVE for name in (
        "start_delay", "selection_pause", "wait_for_planner_result", "poll_period",
        "max_time_before_goal_abortion", "auction_wait", "auction_jitter", "costmap_resolution",
        "inscribed_radius", "inflation_radius", "cost_scaling_factor", "max_goal_range",
        "cluster_join_dist", "cluster_merge_dist", "seen_check_cells", "backoff_search_cells",
        "backoff_inner_cells", "acceptable_goal_cost", "home_attempts", "max_idle_turns")}

    def __post_init__(self) -> None:
        if self.costmap_resolution <= 0 or self.max_goal_range <= 0:
            raise ValueError("thesis.costmap_resolution and max_goal_range must be > 0")
        if self.poll_period <= 0 or self.max_time_before_goal_abortion <= 0:
            raise ValueError("thesis.poll_period and max_time_before_goal_abortion must be > 0")
        if min(self.start_delay, self.selection_pause, self.wait_for_planner_result,
               self.auction_wait, self.auction_jitter) < 0:
            raise ValueError("thesis delays must be >= 0")
        if min(self.seen_check_cells, self.backoff_search_cells, self.backoff_inner_cells,
               self.home_attempts, self.max_idle_turns) < 1:
            raise ValueError("thesis cell counts, home_attempts and max_idle_turns must be >= 1")
