"""Path length of our explorations vs the seed study's (issue #16): perfect-map explorations of
seed-study buildings with a chosen explorer strategy, against ``totalLen`` of
../shared/data/thesis/stats_realistic.csv.

Builds nothing: pass the folder written by ``slam-predict worlds import-thesis`` (with its
thesis_worlds.csv). Each run (one building, one strategy, one seed) appends a JSON line to
OUT/runs.jsonl (``--resume`` skips runs already there); the table printed at the end has, per
building: free area (m²), our path length (m) and sim time (s) per strategy, the seed study's
totalLen, the ratio ours/theirs, coverage and stop reason; then the median ratio per strategy
and the Spearman correlation of the ratio with the free area (trend with building size).

``--gmapping-scans``: the perfect map integrates only the scans GMapping would process (its
linearUpdate / angularUpdate / temporalUpdate), so rooms glimpsed between two processed scans
stay unknown as in the seed study's maps (runs labelled ``<strategy>+gscans``).

Usage: bench/bench_thesis_paths.py WORLDS_DIR ENV [ENV ...] [--strategy thesis nearest]
       [--seed N] [--out DIR] [--resume] [--max-sim-time S] [--gmapping-scans]
       [--thesis KEY=VALUE ...] [--report-only]
"""
from __future__ import annotations

import argparse
import csv
import dataclasses
import json
import os
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from slam_predict.explore import run as runner  # noqa: E402
from slam_predict.slam.gmapping.params import load_params  # noqa: E402
from slam_predict.world.load import load_plan  # noqa: E402

SHARED_DATA = Path(os.environ.get("SLAM_PREDICT_SHARED", ROOT.parent / "shared")) / "data"


def theirs(stats_csv: Path) -> dict:
    """{env: totalLen m} of the seed study."""
    with open(stats_csv) as fh:
        rows = csv.DictReader(fh, skipinitialspace=True)
        return {r["dataset"].strip(): float(r["totalLen"]) for r in rows if r["totalLen"]}


def free_areas(worlds_dir: Path) -> dict:
    with open(worlds_dir / "thesis_worlds.csv") as fh:
        return {r["env"]: float(r["free_area_m2"]) for r in csv.DictReader(fh)
                if r["free_area_m2"]}


def done_runs(path: Path) -> dict:
    runs = {}
    if path.is_file():
        for line in path.read_text().splitlines():
            row = json.loads(line)
            runs[(row["env"], row["strategy"], row["seed"])] = row
    return runs


def run_one(worlds_dir: Path, env: str, strategy: str, seed: int, max_sim_time: float,
            gmapping_scans: bool, overrides: dict, label: str) -> dict:
    settings = runner.load_explore_settings(runner.DEFAULT_CONFIG_DIR, "perfect")
    thesis = dataclasses.replace(settings.explore.thesis, **overrides)
    settings.explore = dataclasses.replace(settings.explore, strategy=strategy, thesis=thesis)
    if gmapping_scans:   # the perfect map integrates only the scans GMapping would process
        g = load_params(Path(runner.DEFAULT_CONFIG_DIR) / "gmapping.yaml")
        settings.perfect = dataclasses.replace(settings.perfect, linearUpdate=g.linearUpdate,
                                               angularUpdate=g.angularUpdate,
                                               temporalUpdate=g.temporalUpdate)
    world = load_plan(str(worlds_dir / f"{env}.world"))
    summary, loop = runner.explore_world(world, seed, settings, "perfect", max_sim_time)
    goals = loop.explorer.log.counts()
    return {"env": env, "strategy": label, "seed": seed, "distance_m": summary["distance_m"],
            "sim_duration_s": summary["sim_duration_s"], "coverage": summary["coverage"],
            "stop_reason": summary["stop_reason"], "stalls": summary["stalls"],
            "wall_time_s": summary["wall_time_s"], "goals": goals}


def spearman(x, y) -> float:
    rx, ry = np.argsort(np.argsort(x)), np.argsort(np.argsort(y))
    return float(np.corrcoef(rx, ry)[0, 1]) if len(x) > 2 else float("nan")


def report(rows: list, strategies: list, their_len: dict, areas: dict) -> None:
    envs = sorted({r["env"] for r in rows}, key=lambda e: areas.get(e, 0.0))
    head = "| building | free m² | " + " | ".join(
        f"{s} m | {s} s | {s} ratio | {s} cov | {s} stop" for s in strategies) + " | theirs m |"
    print(head)
    print("|" + "---|" * (head.count("|") - 1))
    ratios = {s: [] for s in strategies}
    for env in envs:
        cells = [env, f"{areas.get(env, float('nan')):.0f}"]
        for s in strategies:
            runs = [r for r in rows if r["env"] == env and r["strategy"] == s]
            if not runs:
                cells += ["-"] * 5
                continue
            dist = float(np.mean([r["distance_m"] for r in runs]))
            ratio = dist / their_len[env] if env in their_len else float("nan")
            ratios[s].append((areas.get(env, 0.0), ratio))
            cells += [f"{dist:.0f}", f"{np.mean([r['sim_duration_s'] for r in runs]):.0f}",
                      f"{ratio:.2f}", f"{np.mean([r['coverage'] for r in runs]):.3f}",
                      ",".join(sorted({r["stop_reason"] for r in runs}))]
        cells.append(f"{their_len.get(env, float('nan')):.0f}")
        print("| " + " | ".join(cells) + " |")
    for s in strategies:
        if ratios[s]:
            area, ratio = np.array(ratios[s]).T
            print(f"{s}: median ratio ours/theirs {np.median(ratio):.2f} over {len(ratio)} "
                  f"buildings; Spearman(ratio, free area) {spearman(area, ratio):.2f}")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("worlds_dir", type=Path)
    parser.add_argument("envs", nargs="+")
    parser.add_argument("--strategy", nargs="+", default=["thesis"])
    parser.add_argument("--seed", type=int, nargs="+", default=[0])
    parser.add_argument("--out", type=Path, default=Path("out/thesis_paths"))
    parser.add_argument("--resume", action="store_true")
    parser.add_argument("--max-sim-time", type=float, default=10800.0)
    parser.add_argument("--report-only", action="store_true")
    parser.add_argument("--thesis", nargs="+", default=[], metavar="KEY=VALUE",
                        help="override thesis parameters (numbers), e.g. inflation_radius=0.55")
    parser.add_argument("--gmapping-scans", action="store_true",
                        help="perfect map from GMapping's processed scans only (linearUpdate, "
                             "angularUpdate, temporalUpdate of config/gmapping.yaml)")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    jsonl = args.out / "runs.jsonl"
    runs = done_runs(jsonl) if (args.resume or args.report_only) else {}
    overrides = {k: float(v) for k, v in (item.split("=", 1) for item in args.thesis)}
    suffix = ("+gscans" if args.gmapping_scans else "") + "".join(
        f"[{item}]" for item in args.thesis)
    if not args.report_only:
        for env in args.envs:
            for strategy in args.strategy:
                for seed in args.seed:
                    label = strategy + suffix
                    if (env, label, seed) in runs:
                        continue
                    row = run_one(args.worlds_dir, env, strategy, seed, args.max_sim_time,
                                  args.gmapping_scans, overrides, label)
                    runs[(env, label, seed)] = row
                    with open(jsonl, "a") as fh:
                        fh.write(json.dumps(row) + "\n")
                    print(json.dumps(row), flush=True)
    rows = [r for r in runs.values() if r["env"] in args.envs]
    labels = [s + suffix for s in args.strategy]
    report(rows, labels, theirs(SHARED_DATA / "thesis" / "stats_realistic.csv"),
           free_areas(args.worlds_dir))
    return 0


if __name__ == "__main__":
    sys.exit(main())
