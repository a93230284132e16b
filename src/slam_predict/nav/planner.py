"""Global planner: navfn / global_planner costs, exact 8-connected search, goal tolerance.

Cell costs follow the chosen planner (ros_interfaces.md §3.4):

* ``navfn/NavfnROS``: c ≤ 252 → 50 + 0.8·c; INSCRIBED and LETHAL blocked; NO_INFORMATION →
  253 when ``allow_unknown`` (else blocked); the outer ring of the map blocked;
* ``global_planner/GlobalPlanner``: c < lethal_cost − 1 (or unknown when allowed) →
  min(c·cost_factor + neutral_cost, lethal_cost − 1); others blocked.

Entering a cell costs its value times the step length in cells (1 or √2). The search
(:func:`slam_predict.nav.kernels.grid_search`, A* with a consistent heuristic) returns the
cheapest such path — where navfn interpolates a potential field and descends its gradient, we
return the exact optimum of the 8-connected cost (deviation documented). When the goal cell is
blocked or unreachable, the plan ends at the reachable cell nearest the goal within
±``default_tolerance`` (navfn's rule). The search runs on the bounding box of the known cells,
start and goal, grown by ``search_margin`` m, so a mostly unknown 200 m × 200 m SLAM map costs
no more than the explored part.

Extension (start escape, issue #5): navfn only clears the robot's own cell, so a robot whose
centre stands in the INSCRIBED band of a wall (pinned against it after a stall) gets no plan to
anywhere, every goal is ABORTED and the explorer blacklists every frontier. When — and only
when — the ordinary search finds nothing and the start cell is INSCRIBED or LETHAL, the search is
repeated with the INSCRIBED cells within ``escape_radius`` m of the start (default: the
footprint's circumscribed radius, how far the robot must move to get its whole footprint off
the band) usable at the planner's highest cost; LETHAL cells stay blocked. Plans that succeed
today are unchanged.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from slam_predict.nav.changes import KnownBox, WriteLog, equal_within, log_of
from slam_predict.nav.config import MoveBaseConfig
from slam_predict.nav.costmap import (
    INSCRIBED,
    LETHAL,
    NO_INFORMATION,
    Costmap,
    footprint_radii,
    make_footprint,
)
from slam_predict.nav.search import SearchWork, search_codes


@dataclass
class Plan:
    """A global plan: ``poses`` (n, 3) x, y, yaw in the costmap frame; ``cost`` in planner
    units; ``length`` m; ``reaches_goal``: the end cell is the goal cell."""

    poses: np.ndarray
    cost: float
    length: float
    reaches_goal: bool

    def __len__(self) -> int:
        return len(self.poses)


def navfn_cost_table(allow_unknown: bool) -> np.ndarray:
    """Travel cost (float, inf = blocked) per costmap value 0–255 of navfn's
    NavFn::setCostmap: c ≤ 252 → 50 + 0.8·c, NO_INFORMATION → 253 when allowed."""
    c = np.arange(256, dtype=np.float64)
    table = np.where(c < INSCRIBED, 50.0 + 0.8 * c, np.inf)
    if allow_unknown:
        table[NO_INFORMATION] = 253.0
    return table


NAVFN_COST_TABLES = {allowed: navfn_cost_table(allowed) for allowed in (False, True)}


def navfn_cell_costs(costs: np.ndarray, allow_unknown: bool) -> np.ndarray:
    """Per-cell travel costs (float, inf = blocked) of navfn's NavFn::setCostmap (the table's
    value per cell; the outer ring of the map blocked)."""
    out = NAVFN_COST_TABLES[bool(allow_unknown)][costs]
    out[0, :] = np.inf
    out[-1, :] = np.inf
    out[:, 0] = np.inf
    out[:, -1] = np.inf
    return out


def global_planner_cell_costs(costs: np.ndarray, allow_unknown: bool, lethal_cost: int,
                              neutral_cost: int, cost_factor: float,
                              outline_map: bool = True) -> np.ndarray:
    """Per-cell travel costs of global_planner's Expander::getCost."""
    c = costs.astype(np.float64)
    usable = costs < lethal_cost - 1
    if allow_unknown:
        usable |= costs == NO_INFORMATION
    out = np.where(usable, np.minimum(c * cost_factor + neutral_cost, lethal_cost - 1), np.inf)
    if outline_map:
        out[0, :] = np.inf
        out[-1, :] = np.inf
        out[:, 0] = np.inf
        out[:, -1] = np.inf
    return out


def global_planner_cost_table(allow_unknown: bool, lethal_cost: int, neutral_cost: int,
                              cost_factor: float) -> np.ndarray:
    """Travel cost (float, inf = blocked) per costmap value 0–255 of global_planner's
    Expander::getCost (:func:`global_planner_cell_costs` of each value)."""
    values = np.arange(256, dtype=np.uint8).reshape(1, -1)
    return global_planner_cell_costs(values, allow_unknown, lethal_cost, neutral_cost,
                                     cost_factor, outline_map=False)[0]


# The search reads a cell's cost as table[code]: codes 0–255 are costmap values, BLOCKED marks
# the outer ring of the searched box, ESCAPE the INSCRIBED cells the start escape opens.
BLOCKED = 256
ESCAPE = 257


class GlobalPlanner:
    """make_plan over a global costmap with the parameters of ``cfg.base_global_planner``."""

    def __init__(self, cfg: MoveBaseConfig, search_margin: float = 2.0,
                 escape_radius: float | None = None):
        self.kind = cfg.base_global_planner
        self.navfn = cfg.NavfnROS
        self.gp = cfg.GlobalPlanner
        self.search_margin = float(search_margin)
        if escape_radius is None:
            escape_radius = footprint_radii(make_footprint(cfg.global_costmap))[1]
        self.escape_radius = float(escape_radius)
        self.escapes = 0  # plans found only thanks to the start escape
        self.work = SearchWork()
        self.last = LastPlan()
        self.known = KnownBox(NO_INFORMATION)
        self.table = np.full(ESCAPE + 1, np.inf)   # cost per code (ESCAPE's set when used)
        self.table[:256] = self.cost_table()

    @property
    def default_tolerance(self) -> float:
        """The planner's ``default_tolerance`` (m)."""
        return (self.navfn if self.kind == "navfn/NavfnROS" else self.gp).default_tolerance

    def cost_table(self) -> np.ndarray:
        """Travel cost per costmap value 0–255 of the configured planner (inf = blocked)."""
        if self.kind == "navfn/NavfnROS":
            return NAVFN_COST_TABLES[bool(self.navfn.allow_unknown)].copy()
        gp = self.gp
        return global_planner_cost_table(gp.allow_unknown, gp.lethal_cost, gp.neutral_cost,
                                         gp.cost_factor)

    @property
    def outline(self) -> bool:
        """Whether the outer ring of the searched box is blocked (navfn always)."""
        return self.kind == "navfn/NavfnROS" or bool(self.gp.outline_map)

    def cell_costs(self, costs: np.ndarray) -> np.ndarray:
        """Travel cost per cell of the configured planner (inf = blocked)."""
        if self.kind == "navfn/NavfnROS":
            return navfn_cell_costs(costs, self.navfn.allow_unknown)
        gp = self.gp
        return global_planner_cell_costs(costs, gp.allow_unknown, gp.lethal_cost, gp.neutral_cost,
                                         gp.cost_factor, gp.outline_map)

    def _codes(self, sub: np.ndarray) -> np.ndarray:
        """The search's cost codes of a box of costmap values (outer ring BLOCKED when the
        planner outlines the map)."""
        codes = self.work.codes(sub.shape)
        codes[...] = sub
        if self.outline:
            codes[0, :] = BLOCKED
            codes[-1, :] = BLOCKED
            codes[:, 0] = BLOCKED
            codes[:, -1] = BLOCKED
        return codes

    def make_plan(self, costmap: Costmap, start: Sequence[float], goal: Sequence[float],
                  tolerance: float | None = None) -> Plan | None:
        """Plan from ``start`` (x, y[, yaw]) to ``goal`` (x, y, yaw) in the costmap frame.

        Returns None when start or goal is off the map or nothing within the tolerance is
        reachable.
        """
        tol = self.default_tolerance if tolerance is None else float(tolerance)
        s = costmap.world_to_map(float(start[0]), float(start[1]))
        g = costmap.world_to_map(float(goal[0]), float(goal[1]))
        if s is None or g is None:
            return None
        key = (s, tuple(float(v) for v in goal), tol, tuple(costmap.origin),
               float(costmap.resolution))
        if self.last.matches(key, costmap):
            self.escapes += self.last.escaped
            return self.last.result()
        plan, escaped = self._plan(costmap, s, g, goal, tol)
        self.last.remember(key, costmap, plan, escaped)
        self.escapes += escaped
        return plan

    def _plan(self, costmap: Costmap, s, g, goal, tol: float) -> tuple[Plan | None, int]:
        """make_plan's search from cell ``s`` to cell ``g``: (plan or None, 1 when only the
        start escape found it else 0)."""
        tol_cells = int(math.floor(tol / costmap.resolution + 1e-9))
        box = self._search_box(costmap, s, g, tol_cells)
        x0, y0, x1, y1 = box
        sub = costmap.costs[y0:y1, x0:x1]
        codes = self._codes(sub)
        sx, sy = s[0] - x0, s[1] - y0
        gx, gy = g[0] - x0, g[1] - y0
        path, cost = search_codes(codes, self.table, (sx, sy), (gx, gy), tol_cells, self.work)
        escaped = 0
        if len(path) == 0 and INSCRIBED <= sub[sy, sx] <= LETHAL and self.escape_radius > 0:
            if self._open_escape(sub, codes, sx, sy, costmap.resolution):
                path, cost = search_codes(codes, self.table, (sx, sy), (gx, gy), tol_cells,
                                           self.work)
                escaped = int(len(path) > 0)
        if len(path) == 0:
            return None, 0
        path = path + np.array([x0, y0])
        return self._to_plan(costmap, path, float(cost), goal, g), escaped

    def _open_escape(self, sub: np.ndarray, codes: np.ndarray, sx: int, sy: int,
                     resolution: float) -> bool:
        """Mark ESCAPE (usable at the highest traversable cost) in ``codes`` the INSCRIBED
        cells within ``escape_radius`` m of the start cell (outer ring excluded); False if
        there is none."""
        r = int(math.ceil(self.escape_radius / resolution - 1e-9))
        ny, nx = sub.shape
        ys, xs = np.mgrid[max(1, sy - r):min(ny - 1, sy + r + 1),
                          max(1, sx - r):min(nx - 1, sx + r + 1)]
        near = ((xs - sx) ** 2 + (ys - sy) ** 2 <= r * r) & (sub[ys, xs] == INSCRIBED)
        if not near.any():
            return False
        self.table[ESCAPE] = 253.0 if self.kind == "navfn/NavfnROS" else float(
            self.gp.lethal_cost - 1)
        codes[ys[near], xs[near]] = ESCAPE
        return True

    def _search_box(self, costmap: Costmap, s, g, tol_cells: int):
        """Cells [x0, x1) x [y0, y1) worth searching: known cells, start, goal window, margin."""
        kx0, ky0, kx1, ky1 = self.known.of(costmap)
        xs = [s[0], g[0] - tol_cells, g[0] + tol_cells]
        ys = [s[1], g[1] - tol_cells, g[1] + tol_cells]
        if kx0 >= 0:
            xs += [int(kx0), int(kx1) - 1]
            ys += [int(ky0), int(ky1) - 1]
        margin = int(math.ceil(self.search_margin / costmap.resolution)) + 1
        x0 = max(0, min(xs) - margin)
        y0 = max(0, min(ys) - margin)
        x1 = min(costmap.size_x, max(xs) + margin + 1)
        y1 = min(costmap.size_y, max(ys) + margin + 1)
        return x0, y0, x1, y1

    @staticmethod
    def _to_plan(costmap: Costmap, path: np.ndarray, cost: float, goal, goal_cell) -> Plan:
        wx, wy = costmap.map_to_world(path[:, 0], path[:, 1])
        xy = np.stack([wx, wy], axis=1)
        reaches = bool(path[-1, 0] == goal_cell[0] and path[-1, 1] == goal_cell[1])
        if reaches:
            xy[-1] = (float(goal[0]), float(goal[1]))
        yaw = np.zeros(len(xy))
        if len(xy) > 1:
            d = np.diff(xy, axis=0)
            yaw[:-1] = np.arctan2(d[:, 1], d[:, 0])
        yaw[-1] = float(goal[2]) if len(goal) > 2 else 0.0
        length = float(np.sum(np.hypot(*np.diff(xy, axis=0).T))) if len(xy) > 1 else 0.0
        return Plan(np.column_stack([xy, yaw]), cost, length, reaches)


class LastPlan:
    """The last make_plan's inputs and result. A plan depends only on the start cell, the goal
    pose, the tolerance, the costmap's geometry and its costs, so a request equal to the last
    one in all of them gets the same plan without a search (move_base re-plans every
    1/planner_frequency s and on every controller failure, also while the robot stands still
    on an unchanged costmap). The costs are compared with a copy; for a costmap with a write
    log only inside the box written since the copy was last brought up to date (outside it
    the costs still equal the copy), else whole."""

    def __init__(self):
        self.key = None
        self.costs = np.zeros((0, 0), np.uint8)
        self.plan: Plan | None = None
        self.escaped = 0
        self._log: WriteLog | None = None   # the log the copy is in step with, at _count
        self._count = 0

    def _written(self, costmap, costs: np.ndarray):
        """The box where ``costs`` may differ from the copy: None (nowhere), or
        (x0, y0, x1, y1)."""
        log = log_of(costmap)
        if log is None or log is not self._log:
            return (0, 0, costs.shape[1], costs.shape[0])
        return log.since(self._count)

    def _in_step(self, costmap) -> None:
        """The copy now equals the costmap's costs: note where its log stands."""
        log = log_of(costmap)
        self._log = log
        self._count = 0 if log is None else log.count

    def matches(self, key, costmap) -> bool:
        """True when ``key`` and the costmap's costs equal the last request's."""
        costs = costmap.costs
        if key != self.key or costs.shape != self.costs.shape:
            return False
        box = self._written(costmap, costs)
        if box is not None and not equal_within(np.ascontiguousarray(costs), self.costs, *box):
            return False
        self._in_step(costmap)
        return True

    def remember(self, key, costmap, plan: Plan | None, escaped: int) -> None:
        """Keep a request and its result (the costs are copied, where they may differ)."""
        self.key, self.plan, self.escaped = key, plan, escaped
        costs = costmap.costs
        if self.costs.shape != costs.shape:
            self.costs = costs.copy()
        else:
            box = self._written(costmap, costs)
            if box is not None:
                x0, y0, x1, y1 = box
                self.costs[y0:y1, x0:x1] = costs[y0:y1, x0:x1]
        self._in_step(costmap)
    def result(self) -> Plan | None:
        """A copy of the last plan (None when it found none)."""
        plan = self.plan
        return None if plan is None else Plan(plan.poses.copy(), plan.cost, plan.length,
                                              plan.reaches_goal)
