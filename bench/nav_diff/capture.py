"""Capture the local planner's cycles of an in-process episode for the real base_local_planner.

:func:`capture` runs ``slam_predict.collect.episode.run_episode`` (one world, one seed, a
settings file, sim time capped) with the navigator's TrajectoryPlanner wrapped: every
``find_best_path`` call is written to ``cycles.bin`` (costmap, pose, velocity, plan, our
command; ``slam_predict.formats.nav_cycles``) and what our side did to ``ours.npz``: sim time
(s), command (vx m/s, vθ rad/s), cost, the kind of command (:class:`Chosen` value), the mode
the cycle began in, whether the shrunk footprint scored it, and whether TrajectoryPlannerROS's
goal-tolerance branch (stop / rotate to goal) replaced the command. Every navfn ``make_plan``
call goes to ``plans.bin`` / ``ours_plans.npz`` (``bench/nav_diff/plans.py``).
"""
from __future__ import annotations

import dataclasses
import functools
import json
import tempfile
from pathlib import Path

import numpy as np
from plans import PlanWriter  # bench/nav_diff/plans.py (this folder)

from slam_predict.collect import episode
from slam_predict.collect.batch import RunSpec
from slam_predict.collect.settings import load_settings
from slam_predict.formats.nav_cycles import Cycle, CycleWriter, LocalMap, write_params
from slam_predict.nav.local_planner import LocalPlanner
from slam_predict.nav.navigator import Navigator
from slam_predict.nav.planner import GlobalPlanner
from slam_predict.nav.planner_modes import Chosen, Mode
from slam_predict.nav.trajectory_planner import TrajectoryPlanner

CHOSEN = {kind: k for k, kind in enumerate(Chosen)}
MODES = {mode: k for k, mode in enumerate(Mode)}


class Recorder:
    """The hooks' shared state: the planner captured and the rows of ours.npz."""

    def __init__(self, folder: Path):
        self.folder = folder
        self.writer = CycleWriter(folder / "cycles.bin")
        self.plans = PlanWriter(folder)
        self.planner: TrajectoryPlanner | None = None
        self.t = 0.0
        self.chosen: Chosen | None = None
        self.rows: list[list[float]] = []

    def before(self, tp: TrajectoryPlanner, costmap, pose, vel) -> list[float]:
        """Write the cycle's input; returns its row (completed by :meth:`after`)."""
        if self.planner is None:
            self.planner = tp
            write_params(self.folder / "params.txt", tp.cfg, tp.footprint, tp.sim_period)
        body = tp.cfg.escape_footprint_margin > 0 and tp.footprint_at(costmap, pose) is tp.body
        self.chosen = None
        row = [len(self.rows), self.t, 0.0, 0.0, 0.0, -1, MODES[tp.state.mode], float(body), 0.0]
        self._pending = (costmap, tuple(map(float, pose[:3])), (float(vel[0]), float(vel[1])),
                         tp.plan.copy())
        return row

    def after(self, row: list[float], best) -> None:
        costmap, pose, vel, plan = self._pending
        local = LocalMap(costmap.costs, (float(costmap.origin[0]), float(costmap.origin[1])),
                         float(costmap.resolution))
        self.writer.cycle(Cycle(int(row[0]), self.t, pose, vel, plan,
                                (float(best.xv), float(best.thetav)), local))
        row[2:6] = [best.xv, best.thetav, best.cost, CHOSEN.get(self.chosen, -1)]
        self.rows.append(row)

    def close(self) -> dict:
        self.writer.close()
        plans = self.plans.close()
        names = ("index", "t", "xv", "thetav", "cost", "chosen", "mode", "body", "goal_branch")
        rows = np.array(self.rows, dtype=float).reshape(-1, len(names))
        np.savez_compressed(self.folder / "ours.npz", **{n: rows[:, k] for k, n in
                                                          enumerate(names)})
        return {"cycles": self.writer.cycles, "maps": self.writer.maps, "plans": plans}


def _hooks(rec: Recorder) -> list[tuple[type, str, object]]:
    """(owner, name, replacement) of the wrapped methods."""
    find, create = TrajectoryPlanner.find_best_path, TrajectoryPlanner._create_trajectories
    stop, rotate = LocalPlanner._stop_with_acc_limits, LocalPlanner._rotate_to_goal
    step = Navigator.step
    make_plan = GlobalPlanner.make_plan

    @functools.wraps(find)
    def find_best_path(self, costmap, pose, vel):
        if rec.planner not in (None, self):
            return find(self, costmap, pose, vel)
        row = rec.before(self, costmap, pose, vel)
        best = find(self, costmap, pose, vel)
        rec.after(row, best)
        return best

    @functools.wraps(create)
    def create_trajectories(self, *args):
        best, chosen = create(self, *args)
        rec.chosen = chosen
        return best, chosen

    def goal_branch(function):
        @functools.wraps(function)
        def wrapped(self, *args):
            if rec.rows and self.tc is rec.planner:
                rec.rows[-1][8] = 1.0
            return function(self, *args)
        return wrapped

    @functools.wraps(step)
    def nav_step(self, t, *args):
        rec.t = float(t)
        return step(self, t, *args)

    @functools.wraps(make_plan)
    def planner_make_plan(self, costmap, start, goal, tolerance=None):
        escapes = self.escapes
        plan = make_plan(self, costmap, start, goal, tolerance)
        if self.kind == "navfn/NavfnROS":
            tol = self.default_tolerance if tolerance is None else float(tolerance)
            rec.plans.add(rec.t, costmap, start, goal, tol, self.navfn.allow_unknown, plan,
                          self.escapes > escapes)
        return plan

    return [(TrajectoryPlanner, "find_best_path", find_best_path),
            (GlobalPlanner, "make_plan", planner_make_plan),
            (TrajectoryPlanner, "_create_trajectories", create_trajectories),
            (LocalPlanner, "_stop_with_acc_limits", goal_branch(stop)),
            (LocalPlanner, "_rotate_to_goal", goal_branch(rotate)),
            (Navigator, "step", nav_step)]


def capture(world: Path, seed: int, settings_file: Path, sim_time_s: float,
            folder: Path) -> dict:
    """Run the episode with the hooks; writes params.txt, cycles.bin, ours.npz and
    episode.json (the run's summary) into ``folder``; returns the counts."""
    folder.mkdir(parents=True, exist_ok=True)
    settings = load_settings(str(settings_file))
    settings = dataclasses.replace(
        settings, sensor_logs=False,
        stop=dataclasses.replace(settings.stop, max_sim_time_s=float(sim_time_s)))
    rec = Recorder(folder)
    hooks = _hooks(rec)
    saved = [(owner, name, owner.__dict__[name]) for owner, name, _ in hooks]
    for owner, name, function in hooks:
        setattr(owner, name, function)
    try:
        with tempfile.TemporaryDirectory() as tmp:
            spec = RunSpec(str(world), world.stem, 0, int(seed), str(Path(tmp) / "run_000"))
            run = episode.run_episode(spec, settings)
    finally:
        for owner, name, function in saved:
            setattr(owner, name, function)
    counts = rec.close()
    keep = ("coverage", "distance_m", "sim_duration_s", "stop_reason", "stuck", "seed")
    (folder / "episode.json").write_text(json.dumps({k: run.get(k) for k in keep}) + "\n")
    return counts
