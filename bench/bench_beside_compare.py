#!/usr/bin/env python3
"""Two SLAM algorithms on the same routes: a campaign and its `slam beside` replay, run by run.

Pairs every run of BESIDE (``slam-predict slam beside ROUTES --out BESIDE``) with the route it
replayed in ROUTES and prints, per building, both algorithms' mean ε_t and ε_r over the paired
runs, their ratio (beside ÷ route), the beside back-end's loop closures and its own map's
coverage; then the median ratio, in how many buildings each algorithm is lower (and by more than
20 %), and the Spearman correlation of the two algorithms' per-building ε_t.

    python bench/bench_beside_compare.py data/campaigns/fidelity_seed_study_8 \\
        data/campaigns/karto_beside_8
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np
from scipy.stats import spearmanr

CLEAR_MARGIN = 1.2   # "lower by more than 20 %": the --compare acceptance's threshold


def paired_runs(routes: Path, beside: Path) -> dict[str, list[tuple[dict, dict]]]:
    """{world: [(route record, beside record)]} for every beside run with a metric on both."""
    out: dict[str, list[tuple[dict, dict]]] = {}
    for path in sorted(beside.glob("*/run_*/run.json")):
        mine = json.loads(path.read_text())
        if "route" not in mine:
            continue
        route_json = routes / mine["route"]["run"] / "run.json"
        if not route_json.is_file():
            continue
        theirs = json.loads(route_json.read_text())
        if isinstance(mine.get("metric"), dict) and isinstance(theirs.get("metric"), dict):
            out.setdefault(mine["world"], []).append((theirs, mine))
    return out


def _mean(runs: list[tuple[dict, dict]], which: int, key: str) -> float:
    """Mean of metric ``key`` over the route (0) or beside (1) records of ``runs``."""
    return float(np.mean([r[which]["metric"][key] for r in runs]))


def building_rows(pairs: dict[str, list[tuple[dict, dict]]]) -> list[dict]:
    rows = []
    for world, runs in pairs.items():
        rows.append({"world": world, "runs": len(runs),
                     "free": runs[0][0].get("free_area_m2") or float("nan"),
                     "route_t": _mean(runs, 0, "trans_mean"),
                     "beside_t": _mean(runs, 1, "trans_mean"),
                     "route_r": _mean(runs, 0, "rot_mean"), "beside_r": _mean(runs, 1, "rot_mean"),
                     "closures": float(np.mean([r[1].get("loop_closures", 0) for r in runs])),
                     "map_cov": float(np.mean([r[1].get("map_coverage") or np.nan
                                               for r in runs]))})
    return sorted(rows, key=lambda r: r["free"])


def report(rows: list[dict], route_name: str, beside_name: str) -> str:
    lines = [f"| building | free m² | runs | ε_t {route_name} (m) | ε_t {beside_name} (m) | ratio "
             f"| ε_r {route_name} | ε_r {beside_name} | ratio | loop closures | "
             f"{beside_name} map coverage |", "|---" * 11 + "|"]
    for r in rows:
        lines.append(f"| {r['world']} | {r['free']:.0f} | {r['runs']} | {r['route_t']:.3f} | "
                     f"{r['beside_t']:.3f} | {r['beside_t'] / r['route_t']:.2f} | "
                     f"{r['route_r']:.4f} | {r['beside_r']:.4f} | "
                     f"{r['beside_r'] / r['route_r']:.2f} | {r['closures']:.1f} | "
                     f"{r['map_cov']:.3f} |")
    ratio = np.array([r["beside_t"] / r["route_t"] for r in rows])
    if len(rows) >= 3:
        rho = spearmanr([r["route_t"] for r in rows], [r["beside_t"] for r in rows]).statistic
        lines.append(f"\n{len(rows)} buildings: ε_t ratio {beside_name} ÷ {route_name} median "
                     f"{np.median(ratio):.2f} (range {ratio.min():.2f}–{ratio.max():.2f}); "
                     f"{beside_name} lower in {int((ratio < 1).sum())}, by > 20 % in "
                     f"{int((ratio * CLEAR_MARGIN < 1).sum())}; {route_name} lower by > 20 % in "
                     f"{int((ratio > CLEAR_MARGIN).sum())}; Spearman of the two ε_t {rho:.2f}")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("routes", type=Path, help="the collected campaign (the routes)")
    parser.add_argument("beside", type=Path, help="its `slam beside` folder")
    args = parser.parse_args(argv)
    pairs = paired_runs(args.routes, args.beside)
    if not pairs:
        print(f"no paired runs between {args.routes} and {args.beside}", file=sys.stderr)
        return 2
    first = next(iter(pairs.values()))[0]
    names = ((first[0].get("slam") or {}).get("type", "route"),
             (first[1].get("slam") or {}).get("type", "beside"))
    print(report(building_rows(pairs), *names))
    return 0


if __name__ == "__main__":
    sys.exit(main())
