"""Closed-loop exploration benchmark: wall time of one exploration with the perfect map source,
and the share of it spent in each component; ``--sweep``: every shipped world and ipa plan.

Runs ``explore_world`` (simulator + perfect map + move_base equivalent + explorer, sim time, no
ROS) on each plan (default: the shipped office_1500) and prints: sim time (the thesis reports
20–40 min of simulated time for a 1,500 m² office, its Table 4.1), wall and CPU time, distance,
coverage, stalls, stop reason, the share of wall time per component (simulator, map source,
explorer, navigator) and, inside the navigator, per kernel (rollouts, BFS distance grids,
inflation, grid search) measured with wrappers around them.

``--sweep`` runs worlds/*.world and every ipa plan of ../shared/data/floorplans/ipa (0.05 m/px)
smallest free area first, appends one JSON line per plan to OUT/sweep.jsonl (``--resume`` skips
plans already there), writes each run's explore.json/explore.png to OUT/<plan>/, and prints the
acceptance table: plan, reachable free area, coverage, sim time, path length, stalls, the
number of logged commands beyond the velocity/acceleration limits, wall time, stop reason.

Usage: bench/bench_explore.py [PLAN ...] [--seed N] [--max-sim-time S] [--resolution R]
       bench/bench_explore.py --sweep [--out DIR] [--resume] [--max-sim-time S]
"""
from __future__ import annotations

import argparse
import functools
import json
import os
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from slam_predict.explore import run as runner  # noqa: E402
from slam_predict.nav import kernels, rollout  # noqa: E402
from slam_predict.warmup import warm_all  # noqa: E402
from slam_predict.world.load import load_plan  # noqa: E402

KERNELS = ((rollout, "score_samples", "rollouts"), (kernels, "target_distance", "BFS grids"),
           (kernels, "inflate", "inflation"), (kernels, "grid_search", "global planner search"))
SHARED_DATA = Path(os.environ.get("SLAM_PREDICT_SHARED", ROOT.parent / "shared")) / "data"
COVERAGE_TARGET = 0.95
TOL = 1e-9


def instrument(totals):
    """Wrap the navigation kernels to accumulate their wall time in ``totals``."""
    for module, name, label in KERNELS:
        original = getattr(module, name)

        @functools.wraps(original)
        def timed(*args, _f=original, _label=label, **kwargs):
            start = time.perf_counter()
            try:
                return _f(*args, **kwargs)
            finally:
                totals[_label] = totals.get(_label, 0.0) + time.perf_counter() - start
        setattr(module, name, timed)


def sweep_plans(shared_data=SHARED_DATA):
    """(path, resolution) of every shipped world and ipa plan, smallest free area first."""
    plans = [(p, None) for p in sorted((ROOT / "worlds").glob("*.world"))]
    ipa = Path(shared_data) / "floorplans" / "ipa"
    if ipa.is_dir():
        plans += [(p, 0.05) for p in sorted(ipa.glob("*.png")) if "_gt_" not in p.name]
    else:
        print(f"note: {ipa} not found, ipa plans skipped", file=sys.stderr)

    def area(item):
        world = load_plan(item[0], resolution=item[1])
        return float((~world.occupied).sum()) * world.resolution ** 2
    return sorted(plans, key=area)


def limits_kept(commands) -> bool:
    """True when the logged commands kept max |v|, |ω| and the acceleration limits."""
    if "max_abs_v" not in commands:
        return True
    if commands.get("violations") is not None:
        return commands["violations"] == 0
    return (commands["max_abs_v"] <= commands["limit_v"] + TOL
            and commands["max_abs_w"] <= commands["limit_w"] + TOL
            and commands["max_acc_v"] <= commands["limit_acc_v"] + 1e-6
            and commands["max_acc_w"] <= commands["limit_acc_w"] + 1e-6)


def row(summary) -> dict:
    """The sweep table's figures of one run."""
    cmd = summary["commands"]
    return {"plan": summary["world"], "area_m2": summary["reachable_free_m2"],
            "coverage": summary["coverage"], "sim_min": round(summary["sim_duration_s"] / 60, 1),
            "wall_s": summary["wall_time_s"], "distance_m": round(summary["distance_m"], 1),
            "stalls": summary["stalls"], "stop": summary["stop_reason"],
            "limits_ok": limits_kept(cmd), "violations": cmd.get("violations"),
            "max_v": round(cmd.get("max_abs_v", 0.0), 3),
            "max_w": round(cmd.get("max_abs_w", 0.0), 3),
            "max_acc_v": round(cmd.get("max_acc_v", 0.0), 3),
            "max_acc_w": round(cmd.get("max_acc_w", 0.0), 3),
            "goals": summary["explorer_goals"],
            "pass": (summary["coverage"] >= COVERAGE_TARGET
                     and summary["stop_reason"] == "no_frontiers" and limits_kept(cmd)
                     and summary["stalls"] <= summary["distance_m"] / 500.0)}


def print_table(rows) -> None:
    """The acceptance table (markdown) of the sweep, with totals."""
    print("| plan | reachable m² | coverage | sim min | path m | stalls | limit violations | "
          "wall s | stop | ok |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---|---|")
    for r in rows:
        viol = r.get("violations")
        viol = viol if viol is not None else ("0" if r["limits_ok"] else "> 0")
        print(f"| {r['plan']} | {r['area_m2']:.0f} | {r['coverage']:.3f} | {r['sim_min']:.1f} | "
              f"{r['distance_m']:.0f} | {r['stalls']} | {viol} | {r['wall_s']:.0f} | "
              f"{r['stop']} | {'yes' if r['pass'] else 'NO'} |")
    dist = sum(r["distance_m"] for r in rows)
    stalls = sum(r["stalls"] for r in rows)
    print(f"\n{sum(r['pass'] for r in rows)}/{len(rows)} plans pass; {dist:.0f} m driven, "
          f"{stalls} stalls ({500 * stalls / max(dist, 1e-9):.2f} per 500 m); max |v| "
          f"{max((r['max_v'] for r in rows), default=0):.3f} m/s, |ω| "
          f"{max((r['max_w'] for r in rows), default=0):.3f} rad/s, |dv/dt| "
          f"{max((r['max_acc_v'] for r in rows), default=0):.3f} m/s², |dω/dt| "
          f"{max((r['max_acc_w'] for r in rows), default=0):.3f} rad/s²")


def run_sweep(args, settings) -> int:
    """Explore every sweep plan, record each to OUT/sweep.jsonl and print the table."""
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    record = out / "sweep.jsonl"
    done = {}
    if args.resume and record.is_file():
        for line in record.read_text().splitlines():
            r = json.loads(line)
            done[r["plan"]] = r
    plans = [(Path(p), args.resolution) for p in args.plans] if args.plans else sweep_plans()
    rows = []
    for plan, resolution in plans:
        world = load_plan(plan, resolution=resolution)
        if world.name in done:
            rows.append(done[world.name])
            continue
        summary, loop = runner.explore_world(world, args.seed, settings,
                                             max_sim_time=args.max_sim_time)
        runner.write_outputs(out / world.name, summary, loop)
        r = row(summary)
        rows.append(r)
        with open(record, "a") as fh:
            fh.write(json.dumps(r) + "\n")
        print(f"{r['plan']}: coverage {r['coverage']:.3f}, {r['sim_min']:.1f} sim min, "
              f"{r['wall_s']:.0f} s wall, {r['stop']}, stalls {r['stalls']}, goals {r['goals']}",
              flush=True)
    print()
    print_table(rows)
    return 0 if all(r["pass"] for r in rows) else 1


def run_components(args, settings) -> int:
    """One exploration per plan with the per-component and per-kernel wall-time shares."""
    totals = {}
    instrument(totals)
    for plan in args.plans or [str(ROOT / "worlds" / "office_1500.world")]:
        totals.clear()
        world = load_plan(plan, resolution=args.resolution)
        cpu = time.process_time()
        summary, loop = runner.explore_world(world, args.seed, settings,
                                             max_sim_time=args.max_sim_time)
        cpu = time.process_time() - cpu
        wall = summary["wall_time_s"]
        print(f"== {world.name} ({(~world.occupied).sum() * world.resolution ** 2:.0f} m² free, "
              f"{summary['reachable_free_m2']:.0f} m² reachable), seed {args.seed}")
        print(f"sim time {summary['sim_duration_s'] / 60:.1f} min (thesis, 1,500 m² office: 20–40 "
              f"min) | wall {wall:.1f} s | CPU {cpu:.1f} s | "
              f"{1000 * wall / max(1, len(loop.log.t)):.1f} ms/step")
        print(f"coverage {summary['coverage']:.3f} | distance {summary['distance_m']:.0f} m | "
              f"stalls {summary['stalls']} | stop {summary['stop_reason']} | goals "
              f"{summary['explorer_goals']} | command limits "
              f"{'kept' if limits_kept(summary['commands']) else 'EXCEEDED'}")
        for name, seconds in sorted(summary["timing"].items(), key=lambda kv: -kv[1]):
            print(f"  {name:<12} {seconds:8.1f} s  {100 * seconds / wall:5.1f} %")
        for name, seconds in sorted(totals.items(), key=lambda kv: -kv[1]):
            print(f"    navigator kernel {name:<22} {seconds:8.1f} s  "
                  f"{100 * seconds / wall:5.1f} %")
    return 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("plans", nargs="*", help="plans (default: office_1500; with --sweep: "
                        "every shipped world and ipa plan)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--max-sim-time", type=float, default=4 * 3600.0)
    parser.add_argument("--resolution", type=float)
    parser.add_argument("--sweep", action="store_true", help="acceptance sweep table")
    parser.add_argument("--out", default="/tmp/explore_sweep", help="sweep output folder")
    parser.add_argument("--resume", action="store_true", help="skip plans already in the record")
    args = parser.parse_args()
    warm_all()
    settings = runner.load_explore_settings(ROOT / "config")
    return run_sweep(args, settings) if args.sweep else run_components(args, settings)


if __name__ == "__main__":
    sys.exit(main())
