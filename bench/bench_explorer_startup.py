"""Which runs of a campaign the explorer's start-up rules act on.

The nearest-frontier explorer has two rules that act only before its first goal that is not in
place (slam_predict.explore.explorer, "Start-up"): a goal point within 0.1 m of the robot makes
it face backwards, and an in-place goal move_base ABORTS becomes a drive goal. For every
run.json of a campaign folder this replays the run's start (its world, seed and the campaign's
settings) until the explorer sends a goal that is not in place, or ``--max-sim-time`` passes,
and reports the in-place goals before it and whether either rule acted. A run on which no rule
acted is the same run as on a tree without them: after the first drive goal they never act.

    python bench/bench_explorer_startup.py data/campaigns/fidelity_seed_study
"""
from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench"))
sys.path.insert(0, str(ROOT / "src"))

from bench_no_behaviour_change import world_path  # noqa: E402

from slam_predict.collect.settings import load_settings  # noqa: E402
from slam_predict.explore import explorer as explorer_module  # noqa: E402
from slam_predict.explore.goals import HEADING_UNDEFINED_M, facing  # noqa: E402
from slam_predict.explore.loop import ClosedLoop  # noqa: E402
from slam_predict.world.load import load_plan  # noqa: E402

ACTED: list[str] = []


def watched_facing(point, robot_pose, at_start: bool = False) -> float:
    """goals.facing, noting when its start-up rule decides the heading."""
    if at_start and math.hypot(point[0] - robot_pose[0], point[1] - robot_pose[1]) < \
            HEADING_UNDEFINED_M:
        ACTED.append("faced backwards")
    return facing(point, robot_pose, at_start)


explorer_module.facing = watched_facing


def first_goals(world_name: str, seed: int, settings, max_sim: float) -> list[dict]:
    """The explorer's goals up to its first one not in place: [{t, in_place}]; the rules that
    acted are appended to :data:`ACTED`."""
    world = load_plan(str(world_path(ROOT, world_name)))
    loop = ClosedLoop(world, seed, settings.nav, settings.explore, settings.sim,
                      map_source=settings.slam.type, slam_params=settings.slam.params,
                      compute=settings.compute)
    goals, last = [], None
    while loop.t < max_sim:
        loop.step()
        goal = loop.explorer.goal
        if goal is not None and goal is not last:
            last = goal
            goals.append({"t": round(loop.t, 2), "in_place": bool(goal.in_place)})
            if not goal.in_place:
                break
    ACTED.extend("turn aborted" for g in loop.explorer.log.goals
                 if g["outcome"] == "turn_aborted")
    return goals


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("campaign", help="campaign folder (campaign.json, <world>/run_NNN/run.json)")
    ap.add_argument("--settings", help="settings YAML (default: the runs' settings_file)")
    ap.add_argument("--max-sim-time", type=float, default=120.0, help="s")
    args = ap.parse_args(argv)
    records = sorted(Path(args.campaign).glob("*/run_*/run.json"))
    cache: dict[str, object] = {}
    met = 0
    for path in records:
        run = json.loads(path.read_text())
        name = args.settings or str(ROOT / run["settings_file"])
        settings = cache.setdefault(name, load_settings(name))
        ACTED.clear()
        goals = first_goals(run["world"], int(run["seed"]), settings, args.max_sim_time)
        in_place = sum(g["in_place"] for g in goals)
        met += bool(ACTED)
        print(f"{run['world']} {path.parent.name} seed {run['seed']}: {in_place} in-place "
              f"goal(s) before the first drive goal (t {goals[-1]['t'] if goals else '-'} s); "
              f"rules acted: {', '.join(ACTED) or 'none'}")
    print(f"start-up rules acted on {met} of {len(records)} runs")
    return 0


if __name__ == "__main__":
    sys.exit(main())
