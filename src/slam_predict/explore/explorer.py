"""Frontier exploration: choose frontier goals, watch the navigator, stop when none is left.

Strategies (``strategy``):

* ``thesis``: the modified aau ``explorer`` the seed study ran
  (:mod:`slam_predict.explore.thesis_strategy`, its own rules and the ``thesis`` parameters;
  the rules below do not apply to it).
* ``nearest`` (the thesis' rules as stated in its text): the frontier nearest the robot by
  Euclidean distance (to its nearest cell); frontiers within ``tie_tolerance`` of the nearest
  tie and one is drawn with the seeded generator. The goal point is the frontier cell nearest
  its centroid among those at least ``goal_clearance`` from walls
  (:func:`~slam_predict.explore.frontiers.clear_goal`). The goal is kept while its frontier
  lasts (some frontier cell within ``goal_frontier_radius`` of the chosen frontier's reference
  cell) and replaced when it has been seen.
* ``explore_lite``: explore_lite's cost potential_scale·min_distance·res − gain_scale·size·res
  (its extra ×res included), lowest first, goal = the frontier centroid, re-chosen at every
  tick (a changed target preempts the goal); no progress for ``progress_timeout`` blacklists.

A frontier whose goal point is closer than ``near_frontier_distance`` to the robot (typically
the laser's blind sector behind it) gives an in-place goal: the robot's position, facing it.
Start-up (nearest strategy, until the first goal not in place): a point within 0.1 m of the
robot (Karto's first map: one frontier around it) makes the robot face backwards (its blind
sector); an in-place goal move_base ABORTS (no room to turn) is not blacklisted, the frontier's
next goal drives to its nearest cell ≥ ``near_frontier_distance`` away.
A frontier reached (or timed out) before and still there — it was in a laser shadow from the
goal point — is next sent as its own reference cell, never in place (nearest strategy).

A frontier whose goal was just visited is skipped until the next map arrives (the SLAM map
lags the robot by up to map_update_interval).

Common rules: a goal not reached within its time limit (goal_timeout_factor × first plan length
/ max_vel_x + goal_timeout_offset, recorded) or ABORTED by the navigator is dropped, and the next
goal is a random frontier; an ABORTED goal is blacklisted (frontiers whose goal lies within
``blacklist_radius`` are skipped), as is one reached or timed out ``max_goal_attempts`` times.
Exploration ends when no frontier is left (``no_frontiers``) or all are blacklisted
(``all_frontiers_blacklisted``).

Extension (``blacklist_retries`` > 0; 0, explore_lite's behaviour, by default): when every
frontier left is blacklisted, before stopping, the explorer sends a "look around" goal (the
robot's own position, facing the nearest frontier: the way out, often in the laser's blind
sector, gets scanned into the SLAM map and the next plan starts facing it), waits for the
first map published after it, forgets the points blacklisted because move_base ABORTED (or,
explore_lite strategy, for no progress) and chooses again.
Points blacklisted for ``max_goal_attempts`` stay. At most ``blacklist_retries`` consecutive
rounds; a frontier goal that succeeds restarts the count.

Extension (``min_unknown_width`` m > 0; 0, explore_lite's rule, by default): frontiers border
only unknown space joined to an unknown square that wide, so the unknown slivers GMapping
leaves inside walls grazed by the beams are no frontiers (:mod:`~.frontiers`).

``reachable_frontiers`` (false by default, the rule of older records): only frontiers with a
cell in the free space joined to the robot's cell, as explore_lite's search finds them
(:meth:`~.frontiers.ClusterCache.reachable`).
``reachable_first`` (false by default): the frontiers of that free space first; the others
(free pockets a wall line cuts off) only when none of those is left unblacklisted.
"""
from __future__ import annotations

import logging
import math

import numpy as np

from slam_predict.explore.explore_config import STRATEGIES, ExploreConfig  # noqa: F401
from slam_predict.explore.frontiers import (
    ClusterCache,
    Frontier,
    clear_goal,
    find_frontiers,
    nearest_cell_beyond,
)
from slam_predict.explore.goals import (
    ABORTED,
    PREEMPTED,
    SUCCEEDED,
    ExploreLog,
    Goal,
    GoalClient,
    facing,
)

LOG = logging.getLogger(__name__)
class Explorer:
    """Frontier exploration driven by :meth:`step`; see the module docstring. With
    ``strategy: thesis`` the instance is a
    :class:`~slam_predict.explore.thesis_strategy.ThesisExplorer` (same interface)."""

    def __new__(cls, cfg: ExploreConfig, client: GoalClient, rng: np.random.Generator):
        if cls is Explorer and cfg.strategy == "thesis":
            from slam_predict.explore.thesis_strategy import ThesisExplorer
            return ThesisExplorer(cfg, client, rng)
        return super().__new__(cls)

    def __init__(self, cfg: ExploreConfig, client: GoalClient, rng: np.random.Generator):
        self.cfg = cfg
        self.client = client
        self.rng = rng
        self.goal: Goal | None = None
        self.blacklist: list[np.ndarray] = []
        self.forgettable: list[np.ndarray] = []   # blacklisted by ABORTED / no progress
        self.turn_failed: list[np.ndarray] = []   # in-place start-up goals move_base ABORTED
        self.started = False                      # a goal that is not in place has been sent
        self.retries = 0                          # consecutive blacklist retry rounds
        self._retry_map = None                    # waiting for a map newer than this one
        self.attempts: list[tuple[np.ndarray, int]] = []
        self.random_next = False
        self.frontiers: list[Frontier] = []
        self.recent: list[tuple[np.ndarray, object]] = []
        self._grid = None
        self._clusters = ClusterCache()
        self.log = ExploreLog()
        self._next_tick = -math.inf

    @property
    def done(self) -> bool:
        """True once exploration has stopped."""
        return self.log.stop_reason is not None

    # ------------------------------------------------------------------------------- step
    def step(self, t: float, grid, robot_pose) -> None:
        """Check the current goal, and at ``planner_frequency`` (or at once after a goal ended)
        recompute the frontiers and choose a goal. ``grid``: the SLAM map (None = none yet)."""
        if self.done or grid is None:
            return
        self._grid = grid
        self.recent = [(p, g) for p, g in self.recent if g is grid]
        ended = self._check_goal(t)
        if not ended and t + 1e-9 < self._next_tick:
            return
        self._next_tick = t + 1.0 / self.cfg.planner_frequency
        if self._retry_pending(grid):
            return
        clusters = self._clusters.clusters(grid, self.cfg.min_frontier_size,
                                           self.cfg.min_unknown_width)
        if self.cfg.reachable_frontiers:
            clusters = self._clusters.reachable(grid, robot_pose[:2])
        self.frontiers = find_frontiers(grid, robot_pose[:2], self.cfg.min_frontier_size,
                                        self.cfg.min_unknown_width, clusters)
        candidates = [f for f in self.frontiers if not self.is_blacklisted(f)]
        if self.cfg.reachable_first and candidates:
            reach = {id(c.cells) for c in self._clusters.reachable(grid, robot_pose[:2])}
            candidates = [f for f in candidates if id(f.cells) in reach] or candidates
        if not candidates:
            if self.frontiers and self._start_retry(t, grid, robot_pose):
                return
            self._stop(t, "all_frontiers_blacklisted" if self.frontiers else "no_frontiers")
            return
        # frontiers just visited stay out until the map has been refreshed
        fresh = [f for f in candidates if not self._near(f.goal, [p for p, _ in self.recent])]
        if not fresh:
            return
        if self.cfg.strategy == "explore_lite":
            self._explore_lite(t, fresh, grid.resolution, robot_pose)
        else:
            self._nearest(t, fresh, robot_pose)

    def _check_goal(self, t: float) -> bool:
        """Handle the navigator's outcome or the time limit; True if the goal ended."""
        goal = self.goal
        if goal is None:
            return True
        status = self.client.status()
        if goal.look_around:
            return self._check_look_around(t, status)
        if goal.time_limit is None and self.client.plan_length() is not None:
            goal.time_limit = (self.cfg.goal_timeout_factor * self.client.plan_length()
                               / self.cfg.max_vel_x + self.cfg.goal_timeout_offset)
        if status == SUCCEEDED:
            self._end_goal(t, "succeeded")
            self._count_attempt(goal.frontier_point)
            self.retries = 0
            return True
        if status == ABORTED and goal.in_place and self._at_start():
            # the robot could not turn where it stands: drive to the frontier next time
            self._end_goal(t, "turn_aborted")
            self.turn_failed.append(goal.frontier_point)
            return True
        if status == ABORTED:
            self._end_goal(t, "aborted")
            self._blacklist_failure(goal.frontier_point)
            self.random_next = True
            return True
        if status == PREEMPTED:  # by someone else: just choose again
            self._end_goal(t, "preempted")
            return True
        if goal.time_limit is not None and t - goal.t_sent > goal.time_limit:
            self.client.cancel(t)
            self._end_goal(t, "timeout")
            self._count_attempt(goal.frontier_point)
            self.random_next = True
            return True
        return False

    def _end_goal(self, t: float, outcome: str) -> None:
        goal = self.goal
        if outcome != "replaced":
            self.recent.append((goal.frontier_point, self._grid))
        self.log.goals.append({"target": [round(v, 3) for v in goal.target], "t_sent": goal.t_sent,
                               "t_end": t, "outcome": outcome, "time_limit": goal.time_limit})
        LOG.debug("goal (%.2f, %.2f) %s after %.1f s", goal.target[0], goal.target[1], outcome,
                  t - goal.t_sent)
        self.goal = None

    def _count_attempt(self, point: np.ndarray) -> None:
        for k, (p, n) in enumerate(self.attempts):
            if np.hypot(*(p - point)) <= self.cfg.blacklist_radius:
                self.attempts[k] = (p, n + 1)
                if n + 1 >= self.cfg.max_goal_attempts:
                    self.blacklist.append(p)
                return
        self.attempts.append((point, 1))
        if self.cfg.max_goal_attempts <= 1:
            self.blacklist.append(point)

    def _blacklist_failure(self, point: np.ndarray) -> None:
        """Blacklist a point move_base failed to reach (forgotten by a retry round)."""
        self.blacklist.append(point)
        self.forgettable.append(point)

    # ---------------------------------------------------------------- blacklist retries
    def _start_retry(self, t: float, grid, robot_pose) -> bool:
        """All frontiers blacklisted: start a retry round if one is left (see the module
        docstring); True if started."""
        if self.retries >= self.cfg.blacklist_retries or not self.forgettable:
            return False
        self.retries += 1
        LOG.info("all frontiers blacklisted at %.1f s: look around and retry (%d/%d)", t,
                 self.retries, self.cfg.blacklist_retries)
        if self.goal is not None:
            self.client.cancel(t)
            self._end_goal(t, "cancelled")
        x, y = float(robot_pose[0]), float(robot_pose[1])
        nearest = min(self.frontiers, key=lambda f: f.min_distance)
        target = (x, y, facing(nearest.goal, robot_pose, self._at_start()))
        self.goal = Goal(target, t, np.array([x, y]), 0, 0.0,
                         time_limit=self.cfg.goal_timeout_offset, last_progress=t,
                         look_around=True)
        self.client.send_goal(target, t)
        self._retry_map = grid
        return True

    def _check_look_around(self, t: float, status: int | None) -> bool:
        """The look-around goal ended (any outcome or its time limit)? Then wait for a map."""
        goal = self.goal
        timed_out = t - goal.t_sent > goal.time_limit
        if status not in (SUCCEEDED, ABORTED, PREEMPTED) and not timed_out:
            return False
        if timed_out and status not in (SUCCEEDED, ABORTED, PREEMPTED):
            self.client.cancel(t)
        self.log.goals.append({"target": [round(v, 3) for v in goal.target],
                               "t_sent": goal.t_sent, "t_end": t, "outcome": "look_around",
                               "time_limit": goal.time_limit})
        self.goal = None
        self._retry_map = self._grid   # the next map includes the scans taken while turning
        return True

    def _retry_pending(self, grid) -> bool:
        """True while a retry round waits for its look-around goal or a newer map; once that
        map is here, forget the navigation-failure blacklist."""
        if self._retry_map is None:
            return False
        if (self.goal is not None and self.goal.look_around) or grid is self._retry_map:
            return True
        self._retry_map = None
        self.blacklist = [p for p in self.blacklist if all(p is not q for q in self.forgettable)]
        self.forgettable = []
        self.random_next = False
        return False

    def is_blacklisted(self, frontier: Frontier) -> bool:
        """True when the frontier's reference cell is near a blacklisted point."""
        return self._near(frontier.goal, self.blacklist)

    def _near(self, point: np.ndarray, points: list[np.ndarray]) -> bool:
        """Is ``point`` (x, y m) within blacklist_radius of one of ``points``?"""
        offsets = np.asarray(point, float) - np.asarray(points, float).reshape(-1, 2)
        return bool((np.hypot(offsets[:, 0], offsets[:, 1]) <= self.cfg.blacklist_radius).any())

    def _stop(self, t: float, reason: str) -> None:
        if self.goal is not None:
            self.client.cancel(t)
            self._end_goal(t, "cancelled")
        self.log.stop_reason = reason
        self.log.t_stop = t
        LOG.info("exploration stopped at %.1f s: %s", t, reason)

    # -------------------------------------------------------------------------- strategies
    def _nearest(self, t: float, candidates: list[Frontier], robot_pose) -> None:
        if self.goal is not None and self._goal_alive(candidates):
            return
        if self.random_next:
            choice = candidates[int(self.rng.integers(len(candidates)))]
            self.random_next = False
        else:
            dist = np.array([f.min_distance for f in candidates])
            ties = np.nonzero(dist <= dist.min() + self.cfg.tie_tolerance)[0]
            choice = candidates[int(ties[self.rng.integers(len(ties))])]
        if self._near(choice.goal, self.turn_failed):
            point = nearest_cell_beyond(choice, robot_pose, self.cfg.near_frontier_distance)
            self._send(t, choice, point, robot_pose, in_place=False)
        elif self._attempts_at(choice.goal) == 0:
            self._send(t, choice, clear_goal(choice, self._grid, self.cfg.goal_clearance),
                       robot_pose)
        else:  # reached before, still there (seen from nowhere it went): drive onto it
            self._send(t, choice, choice.goal, robot_pose, in_place=False)

    def _at_start(self) -> bool:
        return not self.started and self.cfg.strategy == "nearest"

    def _attempts_at(self, point: np.ndarray) -> int:
        """Goals for the frontier at ``point`` reached or timed out so far."""
        return max([n for p, n in self.attempts
                    if np.hypot(*(p - point)) <= self.cfg.blacklist_radius], default=0)

    def _goal_alive(self, candidates: list[Frontier]) -> bool:
        target = self.goal.frontier_point
        radius = self.cfg.goal_frontier_radius
        return any(np.min(np.hypot(*(f.cells - target).T)) <= radius for f in candidates)

    def _explore_lite(self, t: float, candidates: list[Frontier], res: float, robot_pose) -> None:
        cfg = self.cfg
        if self.random_next:
            choice = candidates[int(self.rng.integers(len(candidates)))]
            self.random_next = False
        else:
            cost = [cfg.potential_scale * f.min_distance * res - cfg.gain_scale * f.size * res
                    for f in candidates]
            choice = candidates[int(np.argmin(cost))]
        goal = self.goal
        if goal is not None and np.hypot(*(choice.centroid - np.array(goal.target[:2]))) < 0.01:
            if choice.min_distance < goal.min_distance:
                goal.last_progress, goal.min_distance = t, choice.min_distance
            elif t - goal.last_progress > cfg.progress_timeout:
                self._blacklist_failure(goal.frontier_point)
                self.client.cancel(t)
                self._end_goal(t, "no_progress")
            return
        self._send(t, choice, choice.centroid, robot_pose)

    def _send(self, t: float, frontier: Frontier, point, robot_pose, in_place: bool = True) -> None:
        heading = facing(point, robot_pose, self._at_start())
        yaw = heading if self.cfg.goal_yaw == "approach" else 0.0
        near = math.hypot(point[0] - robot_pose[0], point[1] - robot_pose[1])
        in_place = in_place and near < self.cfg.near_frontier_distance
        if in_place:   # a frontier next to the robot (e.g. its blind sector): turn to face it
            point, yaw = robot_pose[:2], heading
        self.started = self.started or not in_place
        if self.goal is not None:
            self._end_goal(t, "replaced")
        target = (float(point[0]), float(point[1]), float(yaw))
        self.goal = Goal(target, t, np.array(frontier.goal, dtype=float), frontier.size,
                         frontier.min_distance, last_progress=t, in_place=in_place)
        self.client.send_goal(target, t)
