"""base_local_planner's TrajectoryPlanner: sample velocities, roll out, score, pick.

Per control cycle (TrajectoryPlanner::findBestPath): the path- and goal-distance grids are
computed by BFS on the local costmap from the plan cells and the local goal (the last plan
point inside the map); then, unless escaping, vx_samples × vtheta_samples forward samples
(vθ = 0 first, then vtheta_samples − 1 values from the window's minimum) are scored, then
in-place rotations (|vθ| ≥ min_in_place_vel_theta, preferred when they bring the point
``heading_lookahead`` ahead closer to the goal and the stuck flag of that side is not set),
and finally, when nothing is legal, the escape velocity backwards. The window is
vx ∈ [max(min_vel_x, v − a·T), max(min(max_vel_x, goal_dist/sim_time, v + a·T), min_vel_x)]
(vθ likewise) with T = sim_period when ``dwa`` else sim_time.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import List, Optional, Tuple

import numpy as np

from slam_predict.geometry import wrap_angle
from slam_predict.nav import kernels, rollout
from slam_predict.nav.config import TrajectoryPlannerConfig
from slam_predict.nav.costmap import INSCRIBED, NO_INFORMATION, Costmap, footprint_cells


@dataclass
class Trajectory:
    """A scored sample: cost (< 0 illegal: −1 collision, −2 no path), velocities, poses."""

    cost: float
    xv: float
    thetav: float
    points: np.ndarray = field(default_factory=lambda: np.empty((0, 3)))


class TrajectoryPlanner:
    """The rollout planner with its stuck/escape state (kept across cycles and goals)."""

    def __init__(self, cfg: TrajectoryPlannerConfig, footprint: np.ndarray, sim_period: float,
                 resolution: float):
        self.cfg = cfg
        self.footprint = np.ascontiguousarray(footprint, dtype=float)
        self.body = shrink_footprint(self.footprint, cfg.escape_footprint_margin)
        self.cycle_footprint = self.footprint   # what this cycle's samples are scored with
        self.sim_period = float(sim_period)
        scale = resolution if cfg.meter_scoring else 1.0
        self.pdist = cfg.path_distance_bias * scale
        self.gdist = cfg.goal_distance_bias * scale
        self.occdist = cfg.occdist_scale * (scale if cfg.meter_scoring_occdist else 1.0)
        self.plan = np.empty((0, 3))
        self.final_goal: Optional[Tuple[float, float]] = None
        self.path_dist = np.zeros((1, 1))
        self.goal_dist = np.zeros((1, 1))
        self.stuck_left = self.stuck_right = False
        self.rotating_left = self.rotating_right = False
        self.escaping = False
        self.reversing = False
        self.prev_xy = (0.0, 0.0)
        self.escape_pose = (0.0, 0.0, 0.0)
        self.escape_move: Optional[Tuple[float, float]] = None   # kept body-safe escape
        self.reverse_start = (0.0, 0.0)

    # --------------------------------------------------------------------------- the plan
    def update_plan(self, plan: np.ndarray) -> None:
        """Set the (transformed, pruned) plan in the local costmap frame."""
        self.plan = np.asarray(plan, dtype=float).reshape(-1, 3)
        self.final_goal = (float(self.plan[-1, 0]), float(self.plan[-1, 1])) if len(self.plan) else None

    def compute_maps(self, costmap: Costmap, pose) -> None:
        """Path and goal distance grids (MapGrid::setPathCells) for the robot at ``pose``."""
        costs = costmap.costs
        if self.path_dist.shape != costs.shape:
            self.path_dist = np.empty(costs.shape)
            self.goal_dist = np.empty(costs.shape)
            self._queue = np.empty((costs.size, 2), np.int32)
        within = np.zeros(costs.shape, np.bool_)
        cells = footprint_cells(costmap, pose, self.footprint)
        if len(cells):
            within[cells[:, 1], cells[:, 0]] = True
        path, goal = path_and_goal_cells(costmap, self.plan)
        cell = costmap.world_to_map(float(pose[0]), float(pose[1]))
        cx, cy = cell if cell is not None else (0, 0)
        radius = self.read_radius(costmap.resolution) if cell is not None else -1
        kernels.target_distance(costs, within, path[:, 0], path[:, 1], self.path_dist,
                                self._queue, cx, cy, radius)
        kernels.target_distance(costs, within, goal[:, 0], goal[:, 1], self.goal_dist,
                                self._queue, cx, cy, radius)

    def read_radius(self, resolution: float) -> int:
        """Cells around the robot whose path/goal distances the rollouts can read: the
        farthest reach in sim_time plus heading_lookahead, plus a margin."""
        c = self.cfg
        reach = c.sim_time * max(abs(c.max_vel_x), abs(c.escape_vel), abs(c.min_vel_x))
        return int(math.ceil((reach + c.heading_lookahead) / resolution)) + 3

    # ---------------------------------------------------------------------------- scoring
    def _score(self, costmap: Costmap, pose, vel, samples: np.ndarray):
        return self._score_with(costmap, pose, vel, samples, self.cycle_footprint)

    def _score_with(self, costmap: Costmap, pose, vel, samples: np.ndarray, footprint):
        c = self.cfg
        return rollout.score_samples(
            np.ascontiguousarray(samples, dtype=float), float(pose[0]), float(pose[1]),
            float(pose[2]), float(vel[0]), float(vel[1]), c.acc_lim_x, c.acc_lim_theta,
            c.sim_time, c.sim_granularity, c.angular_sim_granularity, costmap.costs,
            costmap.origin[0], costmap.origin[1], costmap.resolution, footprint,
            self.path_dist, self.goal_dist, float(costmap.costs.size), self.pdist, self.gdist,
            self.occdist)

    def trajectory_points(self, costmap: Costmap, pose, vel, vx: float, vth: float) -> np.ndarray:
        """The poses of one rolled-out sample (for the ``local_plan`` topic)."""
        c = self.cfg
        out = np.empty((int(max(abs(vx) * c.sim_time / c.sim_granularity,
                                abs(vth) / c.angular_sim_granularity) + 2), 3))
        _, n, *_ = rollout.rollout(
            float(pose[0]), float(pose[1]), float(pose[2]), float(vel[0]), float(vel[1]), vx, vth,
            c.acc_lim_x, c.acc_lim_theta, c.sim_time, c.sim_granularity,
            c.angular_sim_granularity, costmap.costs, costmap.origin[0], costmap.origin[1],
            costmap.resolution, self.footprint, self.path_dist, self.goal_dist,
            float(costmap.costs.size), self.pdist, self.gdist, self.occdist, out)
        return out[:n].copy()

    def check_trajectory(self, costmap: Costmap, pose, vel, vx: float, vth: float) -> bool:
        """Is the sample legal (cost ≥ 0) with the current distance grids?"""
        cost, _ = self._score_with(costmap, pose, vel, np.array([[vx, vth]]), self.footprint)
        return bool(cost[0] >= 0)

    # ------------------------------------------------------------------------ best sample
    def find_best_path(self, costmap: Costmap, pose, vel) -> Trajectory:
        """TrajectoryPlanner::findBestPath: maps, then createTrajectories; cost < 0 = none."""
        self.compute_maps(costmap, pose)
        self.cycle_footprint = self._choose_footprint(costmap, pose)
        return self._create_trajectories(costmap, pose, vel)

    def _choose_footprint(self, costmap: Costmap, pose) -> np.ndarray:
        """``escape_footprint_margin`` > 0 and the footprint already touching an obstacle
        (LETHAL or unknown under its outline) where the footprint shrunk by the margin (the
        body) does not: plan this cycle with the body, so the robot can drive or turn away from
        the obstacle rather than only back up blind. Else the configured footprint."""
        if self.cfg.escape_footprint_margin <= 0 or self._footprint_cost(costmap, pose,
                                                                         self.footprint) >= 0:
            return self.footprint
        if self._footprint_cost(costmap, pose, self.body) >= 0:
            return self.body
        return self.footprint

    @staticmethod
    def _footprint_cost(costmap: Costmap, pose, footprint: np.ndarray) -> float:
        return rollout.footprint_cost(costmap.costs, costmap.origin[0], costmap.origin[1],
                                      costmap.resolution, float(pose[0]), float(pose[1]),
                                      float(pose[2]), footprint)

    def _window(self, pose, vel) -> Tuple[float, float, float, float]:
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

    def _create_trajectories(self, costmap: Costmap, pose, vel) -> Trajectory:
        c = self.cfg
        kept = self._keep_escape_move(costmap, pose, vel)
        if kept is not None:
            return kept
        min_vx, max_vx, min_vth, max_vth = self._window(pose, vel)
        dvx = (max_vx - min_vx) / (c.vx_samples - 1) if c.vx_samples > 1 else 0.0
        dvth = (max_vth - min_vth) / (c.vtheta_samples - 1) if c.vtheta_samples > 1 else 0.0
        best = Trajectory(-1.0, 0.0, 0.0)
        if not self.escaping:
            samples = _forward_samples(min_vx, dvx, min_vth, dvth, c.vx_samples, c.vtheta_samples)
            costs, _ = self._score(costmap, pose, vel, samples)
            for k in range(len(samples)):
                if costs[k] >= 0 and (costs[k] < best.cost or best.cost < 0):
                    best = Trajectory(float(costs[k]), float(samples[k, 0]), float(samples[k, 1]))
        forward = best
        best = self._in_place(costmap, pose, vel, best, min_vth, dvth)
        if c.reverse_when_blocked and not self.escaping and best is forward:
            reverse = self._reverse(costmap, pose, vel, best, min_vth, dvth)
            self.reversing = reverse is not None
            if reverse is not None:
                return reverse
        self.reversing = False
        if best.cost >= 0:
            self._update_flags(best, pose)
            return best
        return self._escape(costmap, pose, vel)

    def _reverse(self, costmap, pose, vel, best: Trajectory, min_vth, dvth) -> Optional[Trajectory]:
        """``reverse_when_blocked``: no in-place rotation won and the best forward sample
        (if any) scores worse than staying put — the robot faces away from its goal where it
        cannot turn — or it is already reversing (kept up while it pays, and for at least
        escape_reset_dist, so that it does not shuttle). Returns the best legal backward arc at
        ``escape_vel`` (vθ over the window) if it scores better than staying, else None."""
        c = self.cfg
        x, y, th = float(pose[0]), float(pose[1]), float(pose[2])
        cell = costmap.world_to_map(x, y)
        if cell is None or c.escape_vel >= 0:
            return None
        here = self._footprint_cost(costmap, pose, self.cycle_footprint)
        if here < 0:
            return None
        stay = (self.pdist * self.path_dist[cell[1], cell[0]]
                + self.gdist * self.goal_dist[cell[1], cell[0]]
                + self.occdist * max(here, float(costmap.costs[cell[1], cell[0]])))
        if best.cost >= 0 and best.cost <= stay and not self.reversing:
            return None
        vths = [min_vth + k * dvth for k in range(c.vtheta_samples)] + [0.0]
        samples = np.array([[c.escape_vel, v] for v in vths])
        costs, _ = self._score(costmap, pose, vel, samples)
        back = _cheapest_legal(samples, costs)
        if back is None or (back.cost >= stay and not self._reverse_committed(x, y)):
            return None
        if not self.reversing:
            self.reverse_start = (x, y)
        self._reset_oscillation(x, y)
        return back

    def _reverse_committed(self, x: float, y: float) -> bool:
        """Reversing and not yet escape_reset_dist from where it began: go on backing up even
        where it no longer pays (else the robot shuttled: 2 cm back, 2 cm forward, for minutes
        — a GMapping run of scuola_secondaria_i_grado_mera_ was stopped as stuck)."""
        return self.reversing and math.hypot(x - self.reverse_start[0],
                                             y - self.reverse_start[1]) < self.cfg.escape_reset_dist

    def _in_place(self, costmap, pose, vel, best: Trajectory, min_vth, dvth) -> Trajectory:
        c = self.cfg
        raw: List[float] = []
        vth = min_vth
        for _ in range(c.vtheta_samples):
            raw.append(vth)
            vth += dvth
        limited = [max(v, c.min_in_place_vel_theta) if v > 0 else min(v, -c.min_in_place_vel_theta)
                   for v in raw]
        samples = np.array([[0.0, v] for v in limited])
        costs, ends = self._score(costmap, pose, vel, samples)
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
            ahead = float(self.goal_dist[cell[1], cell[0]])
            if ahead < heading_dist:
                if (v < 0 and not self.stuck_left) or (v > 0 and not self.stuck_right):
                    best = Trajectory(float(costs[k]), 0.0, float(limited[k]))
                    heading_dist = ahead
        return best

    def _update_flags(self, best: Trajectory, pose) -> None:
        x, y = float(pose[0]), float(pose[1])
        if not best.xv > 0:
            if best.thetav < 0:
                if self.rotating_right:
                    self.stuck_right = True
                self.rotating_left = True
            elif best.thetav > 0:
                if self.rotating_left:
                    self.stuck_left = True
                self.rotating_right = True
            self.prev_xy = (x, y)
        self._reset_oscillation(x, y)
        if self._past_escape_reset(pose):
            self.escaping = False

    def _past_escape_reset(self, pose) -> bool:
        """Farther than escape_reset_dist m or escape_reset_theta rad from the escape pose."""
        ex, ey, eth = self.escape_pose
        return (math.hypot(float(pose[0]) - ex, float(pose[1]) - ey) > self.cfg.escape_reset_dist
                or abs(wrap_angle(float(pose[2]) - eth)) > self.cfg.escape_reset_theta)

    def _reset_oscillation(self, x: float, y: float) -> None:
        if math.hypot(x - self.prev_xy[0], y - self.prev_xy[1]) > self.cfg.oscillation_reset_dist:
            self.rotating_left = self.rotating_right = False
            self.stuck_left = self.stuck_right = False

    def _escape(self, costmap, pose, vel) -> Trajectory:
        """Nothing legal: back up slowly at escape_vel (allowed even through obstacles), or,
        with ``escape_footprint_margin``, the body-safe move of :meth:`_body_safe_escape`."""
        c = self.cfg
        x, y, th = float(pose[0]), float(pose[1]), float(pose[2])
        costs, _ = self._score(costmap, pose, vel, np.array([[c.escape_vel, 0.0]]))
        best = Trajectory(float(costs[0]), c.escape_vel, 0.0)
        self.escape_move = None
        if best.cost == -1.0 and c.escape_footprint_margin > 0:
            safe = self._body_safe_escape(costmap, pose, vel)
            if safe is not None:
                best = safe
                self.escape_move = (safe.xv, safe.thetav)
        self._reset_oscillation(x, y)
        if not self.escaping and best.cost > -2.0:
            self.escape_pose = (x, y, th)
            self.escaping = True
        if self._past_escape_reset(pose):
            self.escaping = False
        if best.cost == -1.0:
            best.cost = 1.0
        return best

    def _keep_escape_move(self, costmap, pose, vel) -> Optional[Trajectory]:
        """The move :meth:`_body_safe_escape` chose, again, while escaping (until
        escape_reset_dist / escape_reset_theta from the escape pose) and while the body still
        rolls it out clear; else None (sample as usual). Choosing afresh every cycle, the
        robot alternated between moves that undid each other (a forward arc, an in-place turn
        back, a step back: office_1500 made no progress for 25 min)."""
        move = self.escape_move
        if move is None or not self.escaping:
            self.escape_move = None
            return None
        if self._past_escape_reset(pose):
            self.escape_move = None
            return None
        costs, _ = self._score_with(costmap, pose, vel, np.array([move]), self.body)
        if costs[0] < 0:
            self.escape_move = None
            return None
        return Trajectory(float(costs[0]), move[0], move[1])

    def _body_safe_escape(self, costmap, pose, vel) -> Optional[Trajectory]:
        """The straight escape collides: when the footprint shrunk by
        ``escape_footprint_margin`` would collide on it too, the best backward arc at escape_vel
        (vθ over the window) that the shrunk footprint rolls out without touching an obstacle,
        scored as usual with it; when no backward arc is clear (the robot has backed into a
        wall), the best such forward arc at −escape_vel; else None (the straight escape
        follows, as the original). No in-place turns: a robot already touching a wall cannot
        turn (Stage refuses the move) while its odometry turns on, so it would turn "in place"
        for ever."""
        c = self.cfg
        backward = self._escape_samples(pose, vel, c.escape_vel)
        costs, _ = self._score_with(costmap, pose, vel, backward, self.body)
        if costs[0] >= 0:
            return None
        best = _cheapest_legal(backward, costs)
        if best is None:
            forward = self._escape_samples(pose, vel, -c.escape_vel)
            costs, _ = self._score_with(costmap, pose, vel, forward, self.body)
            best = _cheapest_legal(forward, costs)
        return best

    def _escape_samples(self, pose, vel, vx: float) -> np.ndarray:
        """(vx, 0) then (vx, vθ) for the vθ samples of the window (vθ ≠ 0)."""
        c = self.cfg
        _, _, min_vth, max_vth = self._window(pose, vel)
        steps = max(c.vtheta_samples - 1, 1)
        vths = [min_vth + k * (max_vth - min_vth) / steps for k in range(c.vtheta_samples)]
        return np.array([[vx, 0.0]] + [[vx, v] for v in vths if v != 0.0])


def _cheapest_legal(samples: np.ndarray, costs: np.ndarray) -> Optional[Trajectory]:
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


def _forward_samples(min_vx, dvx, min_vth, dvth, nvx, nvth) -> np.ndarray:
    """(vx, vθ) in createTrajectories' order: per vx, vθ = 0 then nvth − 1 values."""
    out = []
    vx = min_vx
    for _ in range(nvx):
        out.append((vx, 0.0))
        vth = min_vth
        for _ in range(nvth - 1):
            out.append((vx, vth))
            vth += dvth
        vx += dvx
    return np.array(out, dtype=float)


def adjust_plan_resolution(plan_xy: np.ndarray, resolution: float) -> np.ndarray:
    """MapGrid::adjustPlanResolution: insert points so consecutive ones are ≤ resolution apart
    (a segment of length L > resolution gets ceil(L/resolution) − 1 evenly spaced points)."""
    plan_xy = np.asarray(plan_xy, dtype=float).reshape(-1, 2)
    if len(plan_xy) < 2:
        return plan_xy
    seg = np.diff(plan_xy, axis=0)
    length = np.hypot(seg[:, 0], seg[:, 1])
    steps = np.where(length > resolution, np.ceil(length / resolution), 1).astype(int)
    seg_index = np.repeat(np.arange(len(seg)), steps)
    offsets = np.arange(len(seg_index)) - np.repeat(np.cumsum(steps) - steps, steps)
    frac = offsets / steps[seg_index]
    points = plan_xy[seg_index] + frac[:, None] * seg[seg_index]
    return np.vstack([points, plan_xy[-1:]])


def plan_cells(costmap: Costmap, plan: np.ndarray) -> np.ndarray:
    """(n, 2) cells of the plan's first contiguous run inside the map on known cells (the seeds
    of the path distance, MapGrid::setTargetCells)."""
    return path_and_goal_cells(costmap, plan)[0]


def local_goal_cell(costmap: Costmap, plan: np.ndarray) -> np.ndarray:
    """(1, 2) local goal cell, or (0, 2) (MapGrid::setLocalGoal)."""
    return path_and_goal_cells(costmap, plan)[1]


def path_and_goal_cells(costmap: Costmap, plan: np.ndarray):
    """(path cells (n, 2), local goal cell (≤ 1, 2)) of a plan on a local costmap.

    Path cells: the plan's first contiguous run of points (resolution-adjusted) inside the map
    on known cells (MapGrid::setTargetCells). Local goal (MapGrid::setLocalGoal): the last point
    of that run, except that once the plan is more than 1 m from its start, a point in an
    obstacle (≥ INSCRIBED) right after a free one ends the run there.
    """
    empty = np.empty((0, 2), np.int64)
    if len(plan) == 0:
        return empty, empty
    pts = adjust_plan_resolution(np.asarray(plan, dtype=float)[:, :2], costmap.resolution)
    ox, oy = costmap.origin
    inside = (pts[:, 0] >= ox) & (pts[:, 1] >= oy)
    mx = np.zeros(len(pts), np.int64)
    my = np.zeros(len(pts), np.int64)
    mx[inside] = ((pts[inside, 0] - ox) / costmap.resolution).astype(np.int64)
    my[inside] = ((pts[inside, 1] - oy) / costmap.resolution).astype(np.int64)
    inside &= (mx < costmap.size_x) & (my < costmap.size_y)
    ok = np.zeros(len(pts), bool)
    ok[inside] = costmap.costs[my[inside], mx[inside]] != NO_INFORMATION
    if not ok.any():
        return empty, empty
    first = int(np.argmax(ok))
    rest = ok[first:]
    stop = first + (len(rest) if rest.all() else int(np.argmin(rest)))
    run = np.arange(first, stop)
    path = np.stack([mx[run], my[run]], axis=1)
    away = np.maximum.accumulate(np.hypot(*(pts - pts[0]).T) ** 2 > 1.0)[run]
    blocked = costmap.costs[my[run], mx[run]] >= INSCRIBED
    ends = np.nonzero(away[1:] & blocked[1:] & ~blocked[:-1])[0]
    k = ends[0] if len(ends) else len(run) - 1   # the point before the first such break
    return path, path[k:k + 1]
