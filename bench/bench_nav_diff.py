"""Differential check: our base_local_planner port (nav/trajectory_planner.py) against the real
``base_local_planner::TrajectoryPlanner`` of ros-planning/navigation, cycle by cycle on the same
input.

Each case is one in-process episode (``collect.episode.run_episode``: world, seed, settings file,
sim time capped) whose local planner cycles are captured (``bench/nav_diff/capture.py``: every
``find_best_path`` call's local costmap, pose, odometry velocity and plan as
TrajectoryPlannerROS passes them on, and our command). The real planner
(``bench/nav_diff/driver.cpp``, one instance per case, updatePlan + findBestPath per cycle) is
fed the same cycles open loop: our engine drove the robot, so every cycle compares both on one
input. Identical = same (vx, vθ) within 1e-6.

Prints per case: cycles; identical (%); max |Δvx| (m/s) and |Δvθ| (rad/s); max |Δcost| over
identical cycles; cycles where one of our extensions acted (``reverse_when_blocked``,
``escape_footprint_margin``, ``escape_alternate``: not in base_local_planner) or where the two
planners began the cycle in different escape modes (a consequence of an earlier difference);
then the same figures on the remaining cycles ("upstream rules"), and the first differing cycle
of those with both candidates' costs (ours / real scorer).

``--navfn`` adds a table for the global planner: the real navfn
(``bench/nav_diff/navfn_driver.cpp``, NavfnROS::makePlan's steps) on every navfn ``make_plan``
request of the episode (global costmap, start, goal, tolerance; ``plans.bin``), against our
plan: same outcome (plan or none), same end point, length ratio, Hausdorff distance. Our search
is an exact 8-connected one where navfn descends an interpolated potential
(docs/architecture.md), so the paths are not expected to be identical.

``--replay`` adds a table: our planner replayed open loop on the captured cycles
(``bench/nav_diff/replay.py``) as is, with our extensions off, with the five rules where the real
one differs switched to its behaviour, with all of these, and with all but one of the five.

Usage: bench/bench_nav_diff.py --upstream DIR [--cases WORLD:SEED:SIM_S ...]
           [--settings YAML] [--worlds DIR] [--out DIR] [--navfn] [--replay] [--details N]
``--upstream`` (or env SLAM_PREDICT_NAV_UPSTREAM) is an export of github.com/ros-planning/navigation
(noetic-devel) outside this repository, built once into ``<out>/build`` with
``bench/nav_diff/build.sh``. Captures are cached in ``<out>/<world>_<seed>_<sim_s>/``
(``params.txt``, ``cycles.bin``, ``ours.npz``, ``episode.json``, ``real.txt``); delete to rerun.
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench" / "nav_diff"))
import capture as cap  # noqa: E402  (bench/nav_diff/capture.py)
import plans as navfn_plans  # noqa: E402  (bench/nav_diff/plans.py)
import replay as rp  # noqa: E402  (bench/nav_diff/replay.py)

from slam_predict.formats.nav_cycles import read_cycles, read_driver_output  # noqa: E402
from slam_predict.nav.config import TrajectoryPlannerConfig  # noqa: E402
from slam_predict.nav.costmap import Costmap  # noqa: E402
from slam_predict.nav.planner_modes import Chosen, Mode  # noqa: E402
from slam_predict.nav.trajectory_planner import TrajectoryPlanner  # noqa: E402

BUILD_SCRIPT = ROOT / "bench" / "nav_diff" / "build.sh"
DRIVER_SOURCE = ROOT / "bench" / "nav_diff" / "driver.cpp"
NAVFN_SOURCE = ROOT / "bench" / "nav_diff" / "navfn_driver.cpp"
READER_SOURCE = ROOT / "bench" / "nav_diff" / "record_reader.h"
SETTINGS = ROOT / "config" / "fidelity" / "seed_study_refit_escape.yaml"
CASES = ("office_b:1761631670:1800", "Borchen4_updated:3744348009:300",
         "office_h:2047434765:300")
TOL = 1e-6
EXTENSION_KINDS = (Chosen.REVERSE, Chosen.BODY_SAFE, Chosen.KEPT_MOVE)
HOW_TO_GET = ("the real base_local_planner is needed: export ros-planning/navigation "
              "(noetic-devel) OUTSIDE this repository, e.g. git archive of base_local_planner "
              "and costmap_2d into UPSTREAM_DIR\nthen pass --upstream UPSTREAM_DIR (or set "
              "SLAM_PREDICT_NAV_UPSTREAM)")


def build_driver(upstream: Path, build: Path) -> Path:
    """Build (or reuse) the drivers; rebuilt when a source or build.sh is newer."""
    binary = build / "nav_diff_driver"
    newest = max(p.stat().st_mtime for p in (DRIVER_SOURCE, NAVFN_SOURCE, READER_SOURCE,
                                             BUILD_SCRIPT))
    if not binary.exists() or newest > binary.stat().st_mtime:
        subprocess.run(["bash", str(BUILD_SCRIPT), str(upstream), str(build)], check=True,
                       stdout=subprocess.DEVNULL)
    return binary


def run_case(case: str, args, driver: Path) -> Path:
    """Capture (cached) and run the real planner on one case; returns its folder."""
    world, seed, sim_s = case.split(":")
    folder = Path(args.out) / f"{world}_{seed}_{sim_s}"
    if not (folder / "episode.json").exists() or (args.navfn
                                                  and not (folder / "plans.bin").exists()):
        cap.capture(Path(args.worlds) / f"{world}.world", int(seed), Path(args.settings),
                    float(sim_s), folder)
    if not (folder / "real.txt").exists():
        subprocess.run([str(driver), str(folder / "params.txt"), str(folder / "cycles.bin"),
                        str(folder / "real.txt")], check=True, stderr=subprocess.DEVNULL)
    return folder


def classify(ours: dict, real: dict) -> dict[str, np.ndarray]:
    """Per-cycle masks: identical command, an extension of ours acted, escape modes differ."""
    kinds = list(Chosen)
    chosen = [kinds[int(k)] if k >= 0 else None for k in ours["chosen"]]
    modes = [list(Mode)[int(m)] for m in ours["mode"]]
    ext = np.array([c in EXTENSION_KINDS or m in (Mode.REVERSING, Mode.KEEPING_MOVE)
                    or (c is Chosen.BACK_UP and xv > 0)
                    for c, m, xv in zip(chosen, modes, ours["xv"], strict=True)])
    ext |= ours["body"] > 0
    ours_escaping = np.array([m in (Mode.ESCAPING, Mode.KEEPING_MOVE) for m in modes])
    real_escaping = np.concatenate([[False], real["escaping"][:-1] > 0])
    same = ((np.abs(ours["xv"] - real["xv"]) <= TOL)
            & (np.abs(ours["thetav"] - real["thetav"]) <= TOL))
    return {"same": same, "ext": ext, "state": ours_escaping != real_escaping}


def figures(ours: dict, real: dict, mask: np.ndarray, same: np.ndarray) -> list[str]:
    """Table cells of the cycles in ``mask``: count, identical %, max |Δv|, |Δθ̇|, |Δcost|."""
    n = int(mask.sum())
    if n == 0:
        return ["0", "–", "–", "–", "–"]
    dv = np.abs(ours["xv"] - real["xv"])[mask].max()
    dw = np.abs(ours["thetav"] - real["thetav"])[mask].max()
    both = mask & same
    dc = np.abs(ours["cost"] - real["cost"])[both].max() if both.any() else float("nan")
    return [str(n), f"{100 * both.sum() / n:.2f}", f"{dv:.3f}", f"{dw:.3f}", f"{dc:.2g}"]


def our_cost_of(folder: Path, index: int, vx: float, vth: float) -> float:
    """Our scorer's cost of a sample in cycle ``index`` (grids and footprint rule are
    state-free; the planner's mode does not enter a sample's cost)."""
    cfg = params_config(folder / "params.txt")
    for cycle in read_cycles(folder / "cycles.bin"):
        if cycle.index != index:
            continue
        local = cycle.costmap
        costmap = Costmap(local.costs, local.origin, local.resolution)
        tp = TrajectoryPlanner(cfg, footprint_of(folder / "params.txt"), sim_period_of(folder),
                               local.resolution)
        tp.update_plan(cycle.plan)
        tp.compute_maps(costmap, cycle.pose)
        footprint = tp.footprint_at(costmap, cycle.pose)
        cost, _ = tp._score(costmap, cycle.pose, cycle.vel, np.array([[vx, vth]]), footprint)
        return float(cost[0])
    return float("nan")


def _params(path: Path) -> dict[str, list[str]]:
    return {line.split()[0]: line.split()[1:] for line in path.read_text().splitlines() if line}


def params_config(path: Path) -> TrajectoryPlannerConfig:
    values = _params(path)
    kw = {}
    for f in dataclasses.fields(TrajectoryPlannerConfig):
        if f.name in values:
            default = getattr(TrajectoryPlannerConfig(), f.name)
            kw[f.name] = type(default)(float(values[f.name][0]))
    return TrajectoryPlannerConfig(**kw)


def footprint_of(path: Path) -> np.ndarray:
    return np.array(_params(path)["footprint"][1:], dtype=float).reshape(-1, 2)


def sim_period_of(folder: Path) -> float:
    return float(_params(folder / "params.txt")["sim_period"][0])


def first_difference(folder: Path, ours: dict, real: dict, mask: np.ndarray) -> str:
    """The first differing cycle of ``mask``: t, both commands, both scorers' costs."""
    rows = np.nonzero(mask)[0]
    if len(rows) == 0:
        return "none"
    k = int(rows[0])
    mine = our_cost_of(folder, int(ours["index"][k]), real["xv"][k], real["thetav"][k])
    return (f"t {ours['t'][k]:.1f} s: ours ({ours['xv'][k]:.3f}, {ours['thetav'][k]:.3f}) "
            f"cost {ours['cost'][k]:.2f} ours / {real['ours_cost'][k]:.2f} real; real "
            f"({real['xv'][k]:.3f}, {real['thetav'][k]:.3f}) cost {mine:.2f} ours / "
            f"{real['cost'][k]:.2f} real")


def report(case: str, folder: Path, details: int) -> list[str]:
    """The case's two table rows (all cycles; upstream rules only) and its detail lines."""
    ours = dict(np.load(folder / "ours.npz"))
    real = read_driver_output(folder / "real.txt")
    masks = classify(ours, real)
    same, upstream = masks["same"], ~(masks["ext"] | masks["state"])
    name = case.split(":")[0]
    sim = json.loads((folder / "episode.json").read_text())["sim_duration_s"]
    rows = [f"| {name} | {sim:.0f} | all | " + " | ".join(figures(ours, real, ours["t"] >= 0, same))
            + f" | {int(masks['ext'].sum())} / {int(masks['state'].sum())} | "
            + first_difference(folder, ours, real, ~same) + " |",
            f"| {name} | {sim:.0f} | upstream rules | "
            + " | ".join(figures(ours, real, upstream, same)) + " | – | "
            + first_difference(folder, ours, real, upstream & ~same) + " |"]
    for k in np.nonzero(upstream & ~same)[0][:details]:
        rows.append(f"    cycle {int(ours['index'][k])} t {ours['t'][k]:.1f}: ours "
                    f"({ours['xv'][k]:.3f}, {ours['thetav'][k]:.3f}) {ours['cost'][k]:.2f} "
                    f"[{list(Chosen)[int(ours['chosen'][k])].value}, goal branch "
                    f"{int(ours['goal_branch'][k])}]; real ({real['xv'][k]:.3f}, "
                    f"{real['thetav'][k]:.3f}) {real['cost'][k]:.2f}, ours scored real "
                    f"{real['ours_cost'][k]:.2f}; real flags esc {int(real['escaping'][k])} "
                    f"stuck L/R {int(real['stuck_left'][k])}/{int(real['stuck_right'][k])}")
    return rows


FIXES = ("oscillation", "local_goal", "goal_within", "float_pose", "footprint_cells")
REPLAYS = ((), ("no_extensions",), FIXES, FIXES + ("no_extensions",)) + tuple(
    tuple(v for v in FIXES if v != left) + ("no_extensions",) for left in FIXES)
REPLAY_HEADER = ("| case | cycles | as is | extensions off | the 5 upstream rules | all | all: "
                 "cycles with another cost | " + " | ".join(f"all but {v}" for v in FIXES) + " |")


def replay_row(case: str, folder: Path) -> str:
    """Identical (%) with the real planner of our planner replayed open loop on the captured
    cycles, per variant (:data:`REPLAYS`)."""
    real = read_driver_output(folder / "real.txt")
    params = folder / "params.txt"
    cells = [case.split(":")[0], str(len(real["xv"]))]
    for variants in REPLAYS:
        ours = rp.replay(folder, params_config(params), footprint_of(params),
                         sim_period_of(folder), variants)
        same = ((np.abs(ours["xv"] - real["xv"]) <= TOL)
                & (np.abs(ours["thetav"] - real["thetav"]) <= TOL))
        cells.append(f"{100 * same.mean():.2f}")
        if variants == FIXES + ("no_extensions",):
            cells.append(str(int((np.abs(ours["cost"] - real["cost"]) > 1e-9).sum())))
    return "| " + " | ".join(cells) + " |"


NAVFN_HEADER = ("| case | requests | found ours / real | same outcome (%) | ours only (start "
                "escape) | real only | real descent at the cycle limit | same end point (%) "
                "| length ours / real (median, ≥ 1 m) "
                "| Hausdorff median / max (m) |")


def navfn_row(case: str, folder: Path, build: Path) -> str:
    """The global planner's figures of one case (navfn run on our requests)."""
    out = folder / "navfn.txt"
    if not out.exists():
        subprocess.run([str(build / "navfn_diff_driver"), str(folder / "plans.bin"), str(out)],
                       check=True, stderr=subprocess.DEVNULL)
    ours = dict(np.load(folder / "ours_plans.npz"))
    cells = navfn_plans.compare(ours, navfn_plans.read_navfn_output(out),
                                navfn_plans.request_widths(folder / "plans.bin"))
    return "| " + " | ".join([case.split(":")[0]] + cells) + " |"


HEADER = ("| case | sim s | cycles | n | identical (%) | max abs Δvx (m/s) | max abs Δvθ (rad/s) "
          "| max abs Δcost (identical) | extension acted / escape mode differs | first "
          "differing cycle |")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--upstream", default=os.environ.get("SLAM_PREDICT_NAV_UPSTREAM"))
    parser.add_argument("--cases", nargs="+", default=list(CASES), metavar="WORLD:SEED:SIM_S")
    parser.add_argument("--settings", default=str(SETTINGS))
    parser.add_argument("--worlds", default=str(ROOT / "out" / "thesis_worlds"),
                        help="folder of the imported worlds (slam-predict worlds import-thesis)")
    parser.add_argument("--out", default=str(ROOT / "out" / "bench_nav_diff"))
    parser.add_argument("--replay", action="store_true",
                        help="also replay our planner open loop per variant (replay.py)")
    parser.add_argument("--navfn", action="store_true",
                        help="also run the real navfn on our make_plan requests")
    parser.add_argument("--details", type=int, default=0,
                        help="list the first N differing cycles under upstream rules")
    args = parser.parse_args()
    upstream = Path(args.upstream) if args.upstream else None
    if upstream is None or not (upstream / "base_local_planner").is_dir():
        print(f"{args.upstream or '--upstream'}: not given or not a navigation tree; "
              + HOW_TO_GET, file=sys.stderr)
        return 2
    driver = build_driver(upstream, Path(args.out) / "build")
    commit = (Path(args.out) / "build" / "upstream_commit").read_text().strip()
    print(f"real base_local_planner TrajectoryPlanner {commit}; settings {args.settings}")
    print(HEADER)
    print("|" + "---|" * (HEADER.count("|") - 1))
    folders = {}
    for case in args.cases:
        folders[case] = run_case(case, args, driver)
        for line in report(case, folders[case], args.details):
            print(line, flush=True)
    if args.navfn:
        print("\nThe real navfn on our make_plan requests (NavfnROS::makePlan's steps):")
        print(NAVFN_HEADER)
        print("|" + "---|" * (NAVFN_HEADER.count("|") - 1))
        for case, folder in folders.items():
            print(navfn_row(case, folder, Path(args.out) / "build"), flush=True)
    if args.replay:
        print("\nOur planner replayed open loop on the same cycles, identical (%) with the real "
              "one, per variant (bench/nav_diff/replay.py):")
        print(REPLAY_HEADER)
        print("|" + "---|" * (REPLAY_HEADER.count("|") - 1))
        for case, folder in folders.items():
            print(replay_row(case, folder), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
