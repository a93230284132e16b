"""base_local_planner's TrajectoryPlanner: sample velocities, roll out, score, pick.

Per control cycle (TrajectoryPlanner::findBestPath): the path- and goal-distance grids are
computed by BFS on the local costmap from the plan cells and the local goal (nav/map_grid.py);
then, unless escaping, vx_samples × vtheta_samples forward samples (vθ = 0 first, then
vtheta_samples − 1 values from the window's minimum) are scored, then in-place rotations
(|vθ| ≥ min_in_place_vel_theta, preferred when they bring the point ``heading_lookahead`` ahead
closer to the goal and the stuck flag of that side is not set), and finally, when nothing is
legal, the escape velocity backwards. The window is
vx ∈ [max(min_vel_x, v − a·T), max(min(max_vel_x, goal_dist/sim_time, v + a·T), min_vel_x)]
(vθ likewise) with T = sim_period when ``dwa`` else sim_time.

The planner's modes (normal, reversing, escaping, keeping an escape move) and the rule that moves
between them are in nav/planner_modes.py. One footprint rule (:meth:`footprint_at`) is used by
the cycle's scoring and by :meth:`check_trajectory`; only escape moves of the
``escape_footprint_margin`` extension are rolled out with the shrunk footprint (the body).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from slam_predict.nav import rollout
from slam_predict.nav.config import TrajectoryPlannerConfig
from slam_predict.nav.costmap import Costmap
from slam_predict.nav.map_grid import DistanceGrids
from slam_predict.nav.planner_modes import (
    BlindEscapes,
    Chosen,
    Mode,
    Observed,
    Oscillation,
    PlannerState,
    Resets,
    keeps_move,
    next_state,
    reverse_committed,
)

Window = tuple[float, float, float, float]   # min vx, max vx (m/s), min vθ, max vθ (rad/s)


@dataclass
class Trajectory:
    """A scored sample: cost (< 0 illegal: −1 collision, −2 no path), velocities (m/s, rad/s)
    and, for the sample :meth:`TrajectoryPlanner.find_best_path` returns, its poses."""

    cost: float
    xv: float
    thetav: float
    points: np.ndarray = field(default_factory=lambda: np.empty((0, 3)))


class TrajectoryPlanner:
    """The rollout planner with its mode and rotation memory (kept across cycles and goals)."""

    def __init__(self, cfg: TrajectoryPlannerConfig, footprint: np.ndarray, sim_period: float,
                 resolution: float):
        self.cfg = cfg
        self.footprint = np.ascontiguousarray(footprint, dtype=float)
        self.body = shrink_footprint(self.footprint, cfg.escape_footprint_margin)
        self.sim_period = float(sim_period)
        scale = resolution if cfg.meter_scoring else 1.0
        self.pdist = cfg.path_distance_bias * scale
        self.gdist = cfg.goal_distance_bias * scale
        self.occdist = cfg.occdist_scale * (scale if cfg.meter_scoring_occdist else 1.0)
        self.resets = Resets(cfg.escape_reset_dist, cfg.escape_reset_theta)
        self.plan = np.empty((0, 3))
        self.final_goal: tuple[float, float] | None = None
        self.grids = DistanceGrids(cfg.upstream_rules)
        # upstream_rules' other two, one switch each (bench/nav_diff/replay.py weighs them apart)
        self.float_pose = self.upstream_turn_memory = cfg.upstream_rules
        self.state = PlannerState()
        self.oscillation = Oscillation()
        self.blind = BlindEscapes()

    # --------------------------------------------------------------------------- the plan
    def update_plan(self, plan: np.ndarray) -> None:
        """Set the (transformed, pruned) plan in the local costmap frame."""
        self.plan = np.asarray(plan, dtype=float).reshape(-1, 3)
        self.final_goal = ((float(self.plan[-1, 0]), float(self.plan[-1, 1])) if len(self.plan)
                           else None)

    def compute_maps(self, costmap: Costmap, pose) -> None:
        """Path and goal distance grids (MapGrid::setPathCells) for the robot at ``pose``."""
        radius = self.read_radius(costmap.resolution)
        self.grids.update(costmap, pose, self.plan, self.footprint, radius)

    def read_radius(self, resolution: float) -> int:
        """Cells around the robot whose path/goal distances the rollouts can read: the
        farthest reach in sim_time plus heading_lookahead, plus a margin."""
        c = self.cfg
        reach = c.sim_time * max(abs(c.max_vel_x), abs(c.escape_vel), abs(c.min_vel_x))
        return int(math.ceil((reach + c.heading_lookahead) / resolution)) + 3

    # ---------------------------------------------------------------------------- scoring
    def footprint_at(self, costmap: Costmap, pose) -> np.ndarray:
        """The footprint samples from ``pose`` are checked with, by scoring and by
        :meth:`check_trajectory` alike: the configured one, except with
        ``escape_footprint_margin`` > 0 when it already touches an obstacle (LETHAL or unknown
        under its outline) that the footprint shrunk by the margin (the body) clears — then the
        body, so the robot can drive or turn away rather than only back up blind."""
        if (self.cfg.escape_footprint_margin <= 0
                or self._footprint_cost(costmap, pose, self.footprint) >= 0):
            return self.footprint
        if self._footprint_cost(costmap, pose, self.body) >= 0:
            return self.body
        return self.footprint

    def _score(self, costmap: Costmap, pose, vel, samples: np.ndarray, footprint: np.ndarray):
        """(costs (n,), end poses (n, 3)) of the samples (n, 2) rolled out with ``footprint``."""
        c = self.cfg
        return rollout.score_samples(
            np.ascontiguousarray(samples, dtype=float), float(pose[0]), float(pose[1]),
            float(pose[2]), float(vel[0]), float(vel[1]), c.acc_lim_x, c.acc_lim_theta,
            c.sim_time, c.sim_granularity, c.angular_sim_granularity, costmap.costs,
            costmap.origin[0], costmap.origin[1], costmap.resolution, footprint,
            self.grids.path, self.grids.goal, float(costmap.costs.size), self.pdist, self.gdist,
            self.occdist)

    @staticmethod
    def _footprint_cost(costmap: Costmap, pose, footprint: np.ndarray) -> float:
        return rollout.footprint_cost(costmap.costs, costmap.origin[0], costmap.origin[1],
                                      costmap.resolution, float(pose[0]), float(pose[1]),
                                      float(pose[2]), footprint)

    def trajectory_points(self, costmap: Costmap, pose, vel, vx: float, vth: float,
                          footprint: np.ndarray | None = None) -> np.ndarray:
        """The poses (n, 3) of one rolled-out sample up to its first illegal point, with
        ``footprint`` (default: :meth:`footprint_at`)."""
        c = self.cfg
        if footprint is None:
            footprint = self.footprint_at(costmap, pose)
        out = np.empty((int(max(abs(vx) * c.sim_time / c.sim_granularity,
                                abs(vth) / c.angular_sim_granularity) + 2), 3))
        _, n, *_ = rollout.rollout(
            float(pose[0]), float(pose[1]), float(pose[2]), float(vel[0]), float(vel[1]), vx, vth,
            c.acc_lim_x, c.acc_lim_theta, c.sim_time, c.sim_granularity,
            c.angular_sim_granularity, costmap.costs, costmap.origin[0], costmap.origin[1],
            costmap.resolution, footprint, self.grids.path, self.grids.goal,
            float(costmap.costs.size), self.pdist, self.gdist, self.occdist, out)
        return out[:n].copy()

    def check_trajectory(self, costmap: Costmap, pose, vel, vx: float, vth: float) -> bool:
        """Is the sample legal (cost ≥ 0) with the current distance grids and the footprint of
        :meth:`footprint_at` (the rule the cycle's scoring uses)?"""
        samples = np.array([[vx, vth]])
        cost, _ = self._score(costmap, pose, vel, samples, self.footprint_at(costmap, pose))
        return bool(cost[0] >= 0)

    # ------------------------------------------------------------------------ best sample
    def find_best_path(self, costmap: Costmap, pose, vel) -> Trajectory:
        """TrajectoryPlanner::findBestPath: maps, then createTrajectories; cost < 0 = none.
        The returned sample carries its poses; the mode moves on by
        :func:`~slam_predict.nav.planner_modes.next_state`."""
        pose = (float(pose[0]), float(pose[1]), float(pose[2]))
        if self.float_pose:   # findBestPath's Eigen::Vector3f copies
            pose, vel = _as_float32(pose), _as_float32(vel)
        self.compute_maps(costmap, pose)
        footprint = self.footprint_at(costmap, pose)
        best, chosen = self._create_trajectories(costmap, pose, vel, footprint)
        if self.cfg.escape_alternate and chosen not in (Chosen.BACK_UP, Chosen.NO_PATH):
            self.blind = BlindEscapes()
        if chosen in (Chosen.BODY_SAFE, Chosen.KEPT_MOVE):
            footprint = self.body
        best.points = self.trajectory_points(costmap, pose, vel, best.xv, best.thetav, footprint)
        move = (best.xv, best.thetav) if chosen is Chosen.BODY_SAFE else None
        self.state = next_state(self.state, Observed(chosen, pose, move), self.resets)
        if chosen is Chosen.SAMPLE:
            self.oscillation = self.oscillation.after(best.xv, best.thetav, pose[:2],
                                                      self.upstream_turn_memory)
        if chosen is not Chosen.KEPT_MOVE:
            self.oscillation = self.oscillation.reset_if_moved(pose[:2],
                                                               self.cfg.oscillation_reset_dist)
        return best

    def _create_trajectories(self, costmap: Costmap, pose, vel,
                             footprint: np.ndarray) -> tuple[Trajectory, Chosen]:
        """The cycle's command and its kind, by the mode the cycle starts in."""
        c = self.cfg
        if keeps_move(self.state, pose, self.resets):
            kept = self._kept_move(costmap, pose, vel)
            if kept is not None:
                return kept, Chosen.KEPT_MOVE
        window = self._window(pose, vel)
        best = Trajectory(-1.0, 0.0, 0.0)
        if not self.state.escaping:
            best = self._best_forward(costmap, pose, vel, window, footprint)
        forward = best
        best = self._in_place(costmap, pose, vel, best, window, footprint)
        if c.reverse_when_blocked and self.state.may_reverse and best is forward:
            reverse = self._reverse(costmap, pose, vel, best, window, footprint)
            if reverse is not None:
                return reverse, Chosen.REVERSE
        if best.cost >= 0:
            return best, Chosen.SAMPLE
        return self._escape(costmap, pose, vel, footprint)

    def _window(self, pose, vel) -> Window:
        c = self.cfg
        max_vx = c.max_vel_x
        if self.final_goal is not None:
            max_vx = min(max_vx, math.hypot(self.final_goal[0] - pose[0],
                                            self.final_goal[1] - pose[1]) / c.sim_time)
        period = self.sim_period if c.dwa else c.sim_time
        max_vel_x = max(min(max_vx, vel[0] + c.acc_lim_x * period), c.min_vel_x)
        min_vel_x = max(c.min_vel_x, vel[0] - c.acc_lim_x * period)
        max_vel_th = min(c.max_vel_theta, vel[1] + c.acc_lim_theta * period)
        min_vel_th = max(c.min_vel_theta, vel[1] - c.acc_lim_theta * period)
        return min_vel_x, max_vel_x, min_vel_th, max_vel_th

    def _vth_step(self, window: Window) -> float:
        n = self.cfg.vtheta_samples
        return (window[3] - window[2]) / (n - 1) if n > 1 else 0.0

    def _best_forward(self, costmap, pose, vel, window: Window, footprint) -> Trajectory:
        """The cheapest legal forward sample (the first of equal cost), or an illegal one."""
        c = self.cfg
        min_vx, max_vx, min_vth, _ = window
        dvx = (max_vx - min_vx) / (c.vx_samples - 1) if c.vx_samples > 1 else 0.0
        samples = rollout.forward_samples(float(min_vx), float(dvx), float(min_vth),
                                          float(self._vth_step(window)), int(c.vx_samples),
                                          int(c.vtheta_samples))
        costs, _ = self._score(costmap, pose, vel, samples, footprint)
        k = rollout.first_cheapest(costs)
        if k < 0:
            return Trajectory(-1.0, 0.0, 0.0)
        return Trajectory(float(costs[k]), float(samples[k, 0]), float(samples[k, 1]))

    def _in_place(self, costmap, pose, vel, best: Trajectory, window: Window,
                  footprint) -> Trajectory:
        """``best``, or the in-place rotation (no cost above it) whose point heading_lookahead
        ahead is nearest the goal, its side not stuck (upstream)."""
        c = self.cfg
        dvth = self._vth_step(window)
        raw: list[float] = []
        vth = window[2]
        for _ in range(c.vtheta_samples):
            raw.append(vth)
            vth += dvth
        limited = [max(v, c.min_in_place_vel_theta) if v > 0 else min(v, -c.min_in_place_vel_theta)
                   for v in raw]
        costs, ends = self._score(costmap, pose, vel, np.array([[0.0, v] for v in limited]),
                                  footprint)
        heading_dist = math.inf
        for k, v in enumerate(raw):
            if not (costs[k] >= 0 and (costs[k] <= best.cost or best.cost < 0)
                    and (v > dvth or v < -dvth)):
                continue
            ex, ey, eth = ends[k]
            cell = costmap.world_to_map(ex + c.heading_lookahead * math.cos(eth),
                                        ey + c.heading_lookahead * math.sin(eth))
            if cell is None:
                continue
            ahead = float(self.grids.goal[cell[1], cell[0]])
            if ahead < heading_dist and self.oscillation.allows(v):
                best = Trajectory(float(costs[k]), 0.0, float(limited[k]))
                heading_dist = ahead
        return best

    def _reverse(self, costmap, pose, vel, best: Trajectory, window: Window,
                 footprint) -> Trajectory | None:
        """``reverse_when_blocked``: no in-place rotation won and the best forward sample
        (if any) scores worse than staying put — the robot faces away from its goal where it
        cannot turn — or it is already REVERSING. Returns the best legal backward arc at
        ``escape_vel`` (vθ over the window) if it scores better than staying or reversing is
        still committed (:func:`~slam_predict.nav.planner_modes.reverse_committed`), else
        None."""
        c = self.cfg
        cell = costmap.world_to_map(pose[0], pose[1])
        if cell is None or c.escape_vel >= 0:
            return None
        here = self._footprint_cost(costmap, pose, footprint)
        if here < 0:
            return None
        stay = (self.pdist * self.grids.path[cell[1], cell[0]]
                + self.gdist * self.grids.goal[cell[1], cell[0]]
                + self.occdist * max(here, float(costmap.costs[cell[1], cell[0]])))
        if best.cost >= 0 and best.cost <= stay and self.state.mode is not Mode.REVERSING:
            return None
        dvth = self._vth_step(window)
        vths = [window[2] + k * dvth for k in range(c.vtheta_samples)] + [0.0]
        samples = np.array([[c.escape_vel, v] for v in vths])
        costs, _ = self._score(costmap, pose, vel, samples, footprint)
        back = _cheapest_legal(samples, costs)
        if back is None or (back.cost >= stay
                            and not reverse_committed(self.state, pose, self.resets)):
            return None
        return back

    def _escape(self, costmap, pose, vel, footprint) -> tuple[Trajectory, Chosen]:
        """Nothing legal: back up slowly at escape_vel (allowed even through obstacles: a
        collision cost −1 is reported as 1), or, with ``escape_footprint_margin``, the
        body-safe move of :meth:`_body_safe_escape`."""
        c = self.cfg
        costs, _ = self._score(costmap, pose, vel, np.array([[c.escape_vel, 0.0]]), footprint)
        best = Trajectory(float(costs[0]), c.escape_vel, 0.0)
        chosen = Chosen.BACK_UP if best.cost > -2.0 else Chosen.NO_PATH
        if best.cost == -1.0 and c.escape_footprint_margin > 0:
            safe = self._body_safe_escape(costmap, pose, vel)
            if safe is not None:
                best, chosen = safe, Chosen.BODY_SAFE
        if c.escape_alternate and chosen is Chosen.BACK_UP:
            best = self._alternate(costmap, pose, vel, footprint, best)
        if best.cost == -1.0:
            best.cost = 1.0
        return best, chosen

    def _alternate(self, costmap, pose, vel, footprint, back: Trajectory) -> Trajectory:
        """``escape_alternate``: the straight escape back, or forward at −escape_vel when this
        escape began blind right after a blind one (:class:`BlindEscapes`)."""
        if not self.state.escaping:
            self.blind = self.blind.begin(back.cost == -1.0)
        if not self.blind.forward:
            return back
        vx = -self.cfg.escape_vel
        costs, _ = self._score(costmap, pose, vel, np.array([[vx, 0.0]]), footprint)
        return Trajectory(float(costs[0]) if costs[0] >= 0 else -1.0, vx, 0.0)

    def _kept_move(self, costmap, pose, vel) -> Trajectory | None:
        """KEEPING_MOVE: the kept body-safe move again while the body still rolls it out clear,
        else None (the cycle samples as in ESCAPING). Choosing afresh every cycle, the robot
        alternated between moves that undid each other (a forward arc, an in-place turn back,
        a step back: office_1500 made no progress for 25 min)."""
        move = self.state.move
        costs, _ = self._score(costmap, pose, vel, np.array([move]), self.body)
        if costs[0] < 0:
            return None
        return Trajectory(float(costs[0]), move[0], move[1])

    def _body_safe_escape(self, costmap, pose, vel) -> Trajectory | None:
        """The straight escape collides: when the body would collide on it too, the best
        backward arc at escape_vel (vθ over the window) that the body rolls out without
        touching an obstacle, scored as usual with it; when no backward arc is clear (the robot
        has backed into a wall), the best such forward arc at −escape_vel; else None (the
        straight escape follows, as the original). No in-place turns: a robot already touching
        a wall cannot turn (Stage refuses the move) while its odometry turns on, so it would
        turn "in place" for ever."""
        c = self.cfg
        backward = self._escape_samples(pose, vel, c.escape_vel)
        costs, _ = self._score(costmap, pose, vel, backward, self.body)
        if costs[0] >= 0:
            return None
        best = _cheapest_legal(backward, costs)
        if best is None:
            forward = self._escape_samples(pose, vel, -c.escape_vel)
            costs, _ = self._score(costmap, pose, vel, forward, self.body)
            best = _cheapest_legal(forward, costs)
        return best

    def _escape_samples(self, pose, vel, vx: float) -> np.ndarray:
        """(vx, 0) then (vx, vθ) for the vθ samples of the window (vθ ≠ 0)."""
        c = self.cfg
        _, _, min_vth, max_vth = self._window(pose, vel)
        steps = max(c.vtheta_samples - 1, 1)
        vths = [min_vth + k * (max_vth - min_vth) / steps for k in range(c.vtheta_samples)]
        return np.array([[vx, 0.0]] + [[vx, v] for v in vths if v != 0.0])


def _cheapest_legal(samples: np.ndarray, costs: np.ndarray) -> Trajectory | None:
    """The legal (cost ≥ 0) sample of least cost, or None."""
    legal = np.nonzero(costs >= 0)[0]
    if len(legal) == 0:
        return None
    k = int(legal[np.argmin(costs[legal])])
    return Trajectory(float(costs[k]), float(samples[k, 0]), float(samples[k, 1]))


def shrink_footprint(footprint: np.ndarray, margin: float) -> np.ndarray:
    """The polygon with every vertex moved ``margin`` m toward the robot centre in x and in y
    (exact for the rectangular footprints of move_base configs), never past the centre."""
    fp = np.asarray(footprint, dtype=float)
    return np.ascontiguousarray(np.sign(fp) * np.maximum(np.abs(fp) - margin, 0.0))


def _as_float32(values) -> tuple[float, ...]:
    """``values`` rounded to float32, as doubles."""
    return tuple(float(np.float32(v)) for v in values)
