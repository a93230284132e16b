"""``strategy: thesis``: the modified aau ``explorer`` as the seed study ran it, in sim time.

One exploration round (``Explorer::explore``, frontier_selection 5, one robot):

1. Refresh the frontier store on the explorer's costmap built from the current SLAM map
   (:mod:`~slam_predict.explore.thesis_map`, :mod:`~slam_predict.explore.thesis_frontiers`):
   store new frontier cells, drop points near visited / unreachable goals and seen ones.
2. Pause ``selection_pause`` (2 s), then choose: after a failed goal a random stored point
   (frontier_selection 4); otherwise update and sort the clusters and take the nearest valid
   member of the previous goal's cluster, else of the nearest cluster.
3. Send the back-off point of the chosen frontier point (yaw 0, the package's w = 1); no
   back-off point: the frontier point is stored unreachable and a new round starts.
4. Watch the goal as ``move_robot`` does: a first wait of ``wait_for_planner_result`` (3 s,
   cut short by a result), then a state poll every ``poll_period`` (0.5 s); once
   ``max_time_before_goal_abortion`` (90 s) has been counted the goal is cancelled. The goal
   is never replaced while it runs. SUCCEEDED: the frontier point is stored visited and the
   next round uses the cluster strategy; ABORTED, cancelled or any other end: stored
   unreachable, and the next round draws a random point. A new round starts at once.

No goal chosen: while clusters exist, turn in place to the package's goal yaw (45 rad, a
quaternion built from degrees-as-radians) and start again (the state of the last goal is kept);
with none, one more search on the same map (an auction round, pause ``auction_wait`` +
U(0, ``auction_jitter``) s; nearest valid point after a failure); still nothing: exploration
has finished: drive back to the start point (``home_attempts`` goals at most, each with the
time limit) and stop with ``no_frontiers``. The first round starts after ``start_delay``.
Extension: after ``max_idle_turns`` turns in a row with no valid stored point at all the
explorer finishes the same way (``only_invalid_frontiers``; the package turns forever).
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from slam_predict.explore.frontiers import Frontier
from slam_predict.explore.goals import SUCCEEDED, ExploreLog
from slam_predict.explore.thesis_frontiers import FrontierStore
from slam_predict.explore.thesis_map import (
    backoff_goal,
    explorer_costmap,
    frontier_cells,
    seen_mask,
)
from slam_predict.geometry import wrap_angle

LOG = logging.getLogger(__name__)
ACTIVE_STATES = (None, 0, 1)   # no result yet, PENDING, ACTIVE
NAVIGATED = ("frontier", "random", "global")   # goals whose point is stored visited/unreachable


@dataclass
class ThesisGoal:
    """A goal being watched: its kind, target pose, frontier point and polling state."""

    kind: str
    target: tuple[float, float, float]
    t_sent: float
    point: np.ndarray | None
    next_check: float
    elapsed: float
    first_wait: bool = True


class ThesisExplorer:
    """The thesis explorer behind :class:`~slam_predict.explore.explorer.Explorer`'s interface
    (``step``, ``done``, ``log``, ``goal``, ``frontiers``, ``is_blacklisted``)."""

    def __init__(self, cfg, client, rng: np.random.Generator):
        self.cfg = cfg
        self.tc = cfg.thesis
        self.client = client
        self.rng = rng
        self.store = FrontierStore(self.tc.max_goal_range, self.tc.cluster_join_dist,
                                   self.tc.cluster_merge_dist)
        self.log = ExploreLog()
        self.goal: ThesisGoal | None = None
        self.frontiers: list[Frontier] = []
        self.failed_last = False
        self.cluster_id: int | None = None
        self.home: np.ndarray | None = None
        self._select_at: float | None = None
        self._pending: tuple[str, tuple[float, float, float], np.ndarray] | None = None
        self._send_at = math.inf
        self._costmap = None
        self._idle_turns = 0
        self._home_tries = 0
        self._finish_reason: str | None = None

    @property
    def done(self) -> bool:
        """True once exploration has stopped."""
        return self.log.stop_reason is not None

    def is_blacklisted(self, frontier: Frontier) -> bool:
        """True when the cluster's nearest point is not a valid goal (near a visited or
        unreachable one)."""
        return not self.store.is_valid(frontier.goal)

    # ------------------------------------------------------------------------- step
    def step(self, t: float, grid, robot_pose) -> None:
        """Advance the explorer to sim time ``t`` (s) with the current SLAM ``grid`` and the
        robot pose (map frame)."""
        if self.done or grid is None:
            return
        if self.home is None:
            self.home = np.array(robot_pose[:2], dtype=float)
            self.store.visited.append((float(self.home[0]), float(self.home[1])))
            self.store.add_cells(self.home[None, :])     # the package stores it as a frontier too
            self._select_at = t + self.tc.start_delay + self.tc.selection_pause
            self._refresh(grid, robot_pose)
            return
        if self.goal is not None:
            self._watch(t, robot_pose, grid)
            return
        if self._pending is not None:
            if t + 1e-9 >= self._send_at:
                self._send(t, *self._pending)
            return
        if self._select_at is not None and t + 1e-9 >= self._select_at:
            self._select_at = None
            self._select(t, grid, robot_pose)

    def _start_round(self, t: float, grid, robot_pose) -> None:
        """Steps 1-2: refresh the store now, choose after the pause."""
        self._refresh(grid, robot_pose)
        self._select_at = t + self.tc.selection_pause

    def _refresh(self, grid, robot_pose) -> None:
        tc = self.tc
        costmap = explorer_costmap(grid, tc.costmap_resolution, tc.inscribed_radius,
                                   tc.inflation_radius, tc.cost_scaling_factor)
        self._costmap = costmap
        if costmap is None:
            return
        self.store.add_cells(frontier_cells(costmap))
        self.store.clear_goals()
        _, points = self.store.array()
        self.store.remove_seen(seen_mask(costmap, points, tc.seen_check_cells))

    # ------------------------------------------------------------------------ selection
    def _select(self, t: float, grid, robot_pose) -> None:
        """Step 2-3 (see the module docstring)."""
        if self.failed_last:
            point, kind = self.store.random_goal(self.rng), "random"
        else:
            self.store.update_clusters()
            self.store.sort_clusters(robot_pose[:2], self.rng)
            chosen = self.store.cluster_goal(self.cluster_id)
            point, kind = (None, "frontier") if chosen is None else (chosen[0], "frontier")
            if chosen is not None:
                self.cluster_id = chosen[1]
        self._publish_frontiers(robot_pose)
        if point is not None:
            return self._send_backoff(t, kind, point, 0.0, grid, robot_pose)
        if self.store.clusters:
            return self._turn(t, robot_pose)
        self._global_iteration(t, grid, robot_pose)

    def _global_iteration(self, t: float, grid, robot_pose) -> None:
        """No cluster left: one more search (iterate_global_costmap), else finish."""
        self._refresh(grid, robot_pose)
        delay = 0.0
        if self.failed_last:
            point = self.store.nearest_goal(robot_pose[:2])
        else:
            self.store.update_clusters()
            self.store.sort_clusters(robot_pose[:2], self.rng)
            chosen = self.store.auction_goal(robot_pose[:2])
            point = None if chosen is None else chosen[0]
            if chosen is not None:
                self.cluster_id = chosen[1]
            delay = self.tc.auction_wait + float(self.rng.uniform(0.0, self.tc.auction_jitter))
        if point is None:
            self._finish_reason = "no_frontiers"
            return self._go_home(t)
        self._send_backoff(t, "global", point, delay, grid, robot_pose)

    def _send_backoff(self, t: float, kind: str, point: np.ndarray, delay: float, grid,
                      robot_pose) -> None:
        tc = self.tc
        target = None if self._costmap is None else backoff_goal(
            self._costmap, float(point[0]), float(point[1]), tc.backoff_search_cells,
            tc.backoff_inner_cells, tc.acceptable_goal_cost)
        if target is None:   # no back-off point: unreachable, next round at once
            self.store.unreachable.append((float(point[0]), float(point[1])))
            self._log(t, t, kind, (float(point[0]), float(point[1]), 0.0), "no_backoff")
            return self._start_round(t, grid, robot_pose)
        self._idle_turns = 0
        self._queue(t, kind, (float(target[0]), float(target[1]), 0.0), point, delay)

    def _turn(self, t: float, robot_pose) -> None:
        # a random draw may miss the valid points: only turns with none left count
        _, points = self.store.array()
        stuck = not any(self.store.is_valid(p) for p in points)
        self._idle_turns = self._idle_turns + 1 if stuck else 0
        if self._idle_turns > self.tc.max_idle_turns:
            self._finish_reason = "only_invalid_frontiers"
            return self._go_home(t)
        target = (float(robot_pose[0]), float(robot_pose[1]), wrap_angle(self.tc.turn_yaw))
        self._queue(t, "turn", target, None, 0.0)

    def _go_home(self, t: float) -> None:
        if not self.tc.return_home or self._home_tries >= self.tc.home_attempts:
            return self._stop(t, self._finish_reason)
        self._home_tries += 1
        self._queue(t, "home", (float(self.home[0]), float(self.home[1]), 0.0), None, 0.0)

    def _queue(self, t, kind, target, point, delay: float) -> None:
        self._pending = (kind, target, point)
        self._send_at = t + delay
        if delay <= 0:
            self._send(t, kind, target, point)

    def _send(self, t: float, kind: str, target, point) -> None:
        self._pending, self._send_at = None, math.inf
        wait = self.tc.wait_for_planner_result
        self.goal = ThesisGoal(kind, target, t, point, t + wait, wait)
        self.client.send_goal(target, t)

    # ---------------------------------------------------------------------------- watch
    def _watch(self, t: float, robot_pose, grid) -> None:
        """move_robot / turn_robot's waiting loops (see the module docstring)."""
        goal, tc = self.goal, self.tc
        status = self.client.status()
        active = status in ACTIVE_STATES
        if t + 1e-9 < goal.next_check:
            if active or not goal.first_wait:
                return
        elif active and (goal.kind == "turn" or goal.elapsed <= tc.max_time_before_goal_abortion):
            goal.first_wait = False
            goal.elapsed += tc.poll_period
            goal.next_check += tc.poll_period
            return
        if status == SUCCEEDED:
            outcome = "succeeded"
        elif goal.kind != "turn" and goal.elapsed >= tc.max_time_before_goal_abortion:
            self.client.cancel(t)
            outcome = "timeout"
        else:
            outcome = "aborted"
        self._end(t, outcome, robot_pose, grid)

    def _end(self, t: float, outcome: str, robot_pose, grid) -> None:
        goal = self.goal
        self.goal = None
        self._log(goal.t_sent, t, goal.kind, goal.target, outcome)
        if goal.kind == "home":
            if outcome == "succeeded":
                self._home_tries = self.tc.home_attempts
            return self._go_home(t)
        if goal.kind in NAVIGATED:
            point = (float(goal.point[0]), float(goal.point[1]))
            if outcome == "succeeded":
                self.store.visited.append(point)
            else:
                self.store.unreachable.append(point)
            self.failed_last = outcome != "succeeded"
        self._start_round(t, grid, robot_pose)

    def _log(self, t_sent: float, t_end: float, kind: str, target, outcome: str) -> None:
        self.log.goals.append({"target": [round(float(v), 3) for v in target], "t_sent": t_sent,
                               "t_end": t_end, "outcome": outcome, "kind": kind,
                               "time_limit": None if kind == "turn"
                               else self.tc.max_time_before_goal_abortion})
        LOG.debug("%s goal (%.2f, %.2f) %s after %.1f s", kind, target[0], target[1], outcome,
                  t_end - t_sent)

    def _stop(self, t: float, reason: str) -> None:
        self.log.stop_reason = reason
        self.log.t_stop = t
        LOG.info("exploration stopped at %.1f s: %s", t, reason)

    def _publish_frontiers(self, robot_pose) -> None:
        """Clusters as :class:`Frontier` objects (members as cells, nearest member as goal)."""
        out = []
        for cluster in self.store.clusters:   # not updated after a failure: skip gone points
            cells = np.array([self.store.points[m] for m in cluster.members
                              if m in self.store.points], float).reshape(-1, 2)
            if len(cells) == 0:
                continue
            dist = np.hypot(cells[:, 0] - robot_pose[0], cells[:, 1] - robot_pose[1])
            out.append(Frontier(cells, len(cells), cells.mean(axis=0), cells[0],
                                float(dist.min())))
        self.frontiers = out
