#!/usr/bin/env python3
"""Where the fidelity campaign's size trend comes from: ε_t ours ÷ the seed study's per building,
beside the path ratio, the ratio per metre driven and GMapping's starvation under the compute
delay, for each declared part (parts.yaml). docs/notes/fidelity.md, "2026-12-06".

    python bench/bench_fidelity_size_trend.py [CAMPAIGN] [--thesis CSV] [--min-coverage 0.5]
                                              [--parts YAML]
"""
from __future__ import annotations

import argparse
import json
import statistics
from pathlib import Path

import numpy as np
from scipy.stats import spearmanr

from slam_predict.collect.fidelity import read_thesis_table
from slam_predict.collect.fidelity_parts import load_parts

ROOT = Path(__file__).resolve().parents[1]
SMALL_M2, LARGE_M2 = 1200.0, 2200.0


def runs_by_building(campaign: Path, min_coverage: float) -> dict[str, list[dict]]:
    """Every run.json with a metric and coverage ≥ ``min_coverage``, by world."""
    out: dict[str, list[dict]] = {}
    for path in sorted(campaign.glob("*/run_*/run.json")):
        run = json.loads(path.read_text())
        if run.get("metric") and run["coverage"] >= min_coverage:
            out.setdefault(run["world"], []).append(run)
    return out


def building_row(runs: list[dict], theirs: dict) -> dict[str, float]:
    """One building's ratios and compute figures (means over its runs)."""
    mean = statistics.mean
    return {"area": runs[0]["free_area_m2"],
            "ratio": mean(r["metric"]["trans_mean"] for r in runs)
            / theirs["trans_mean"],
            "path": mean(r["distance_m"] for r in runs) / theirs["path_length_mean"],
            "handled_per_m": mean(r["slam_compute"]["scans_handled"] / r["distance_m"]
                                  for r in runs),
            "busy": mean(r["slam_compute"]["busy_s"] / r["sim_duration_s"] for r in runs)}


def within_building_slope(by: dict[str, list[dict]]) -> tuple[float, float, int]:
    """Slope and Spearman of log(ε_t / building mean) on log(path / building mean)."""
    xs, ys = [], []
    for runs in by.values():
        if len(runs) < 2:
            continue
        path = statistics.mean(r["distance_m"] for r in runs)
        error = statistics.mean(r["metric"]["trans_mean"] for r in runs)
        xs += [np.log(r["distance_m"] / path) for r in runs]
        ys += [np.log(r["metric"]["trans_mean"] / error) for r in runs]
    return float(np.polyfit(xs, ys, 1)[0]), float(spearmanr(xs, ys)[0]), len(xs)


def part_line(name: str, rows: list[dict], slope: float) -> str:
    """The markdown row of one part."""
    col = {k: np.array([r[k] for r in rows]) for k in rows[0]}
    small, large = col["area"] < SMALL_M2, col["area"] > LARGE_M2
    per_m = col["ratio"] / col["path"]
    corrected = col["ratio"] / col["path"] ** slope

    def split(values):
        return f"{np.median(values):.2f} ({np.median(values[small]):.2f} / " \
               f"{np.median(values[large]):.2f})"

    def trend(values):
        return spearmanr(values, col["area"])[0]
    return (f"| {name} ({len(rows)}) | {split(col['ratio'])}, trend {trend(col['ratio']):.2f} | "
            f"{split(col['path'])} | {np.median(per_m):.2f}, {trend(per_m):.2f} | "
            f"{np.median(corrected):.2f}, {trend(corrected):.2f} | "
            f"{np.median(col['handled_per_m'][small]):.1f} / "
            f"{np.median(col['handled_per_m'][large]):.1f} | "
            f"{np.median(col['busy'][small]):.2f} / {np.median(col['busy'][large]):.2f} |")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("campaign", nargs="?", default=str(ROOT / "data" / "campaigns" /
                                                          "fidelity_seed_study"))
    parser.add_argument("--thesis", default=str(ROOT.parent / "shared" / "data" / "thesis" /
                                                "stats_realistic.csv"))
    parser.add_argument("--min-coverage", type=float, default=0.5)
    parser.add_argument("--parts", help="declared parts (default: the campaign's parts.yaml, "
                                        "else fidelity_seed_study's, which its successors share)")
    args = parser.parse_args()
    campaign = Path(args.campaign)
    theirs = read_thesis_table(Path(args.thesis))
    parts_file = Path(args.parts) if args.parts else campaign / "parts.yaml"
    if not parts_file.is_file() and not args.parts:
        parts_file = ROOT / "data" / "campaigns" / "fidelity_seed_study" / "parts.yaml"
    parts = load_parts(parts_file)
    by = runs_by_building(campaign, args.min_coverage)
    slope, rho, n = within_building_slope(by)
    print(f"within a building: d log ε_t / d log path = {slope:.2f} (Spearman {rho:.2f}, "
          f"{n} runs)")
    print("| part | ε_t ratio median (< 1,200 / > 2,200 m²), trend with area | path ratio | "
          "ε_t ratio ÷ path ratio: median, trend | ÷ path ratio^slope: median, trend | "
          "scans handled per m (< 1,200 / > 2,200) | GMapping busy share |")
    print("|---|---|---|---|---|---|---|")
    for name, worlds in parts.items():
        rows = [building_row(by[w], theirs[w]) for w in worlds if w in by and w in theirs]
        print(part_line(name, rows, slope))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
