"""What the seed study's odometry error looked like, read off its own tables (issue #16).

Two figures separate a per-run random heading bias (the thesis' text: Stage draws the odometry
error uniformly in [−E/2, +E/2] at startup) from a fixed one (Stage's code: world-file
``odom_error`` values are used as they are, every run):

- **Run-to-run scatter of ε_r.** With a per-run uniform bias b_θ, a run's heading error is
  roughly proportional to |b_θ|, whose coefficient of variation is 1/√3 ≈ 0.58; with a fixed
  bias only the path changes from run to run. The seed study's CV = ``rotError.mean.std`` /
  ``rotError.mean.mean`` per building, against ours per campaign, and how strongly our runs'
  ε_r (divided by their building's mean) follows |b_θ| (Spearman over runs).
- **The heading error that the bias adds.** The realistic setting (2 °/rad) and the optimistic
  one (0 °/rad) differ only by the rotational odometry error, so per building
  D_odo = (ε_r,realistic² − ε_r,optimistic²) / totalRot (rad²/rad) is the heading variance the
  bias adds per radian turned. Constant over buildings means a random walk in the rotation
  driven; its spread and its Spearman correlation with totalRot are printed.

Reads only run.json files (committed) and the thesis tables in ../shared/data/thesis.

Usage: bench/bench_odometry_signature.py [CAMPAIGN_DIR ...] [--min-coverage SHARE]
"""
from __future__ import annotations

import argparse
import csv
import json
import os
import sys
from pathlib import Path

import numpy as np
from scipy.stats import spearmanr

from slam_predict.metric.runs import MIN_COVERAGE

ROOT = Path(__file__).resolve().parents[1]
SHARED_DATA = Path(os.environ.get("SLAM_PREDICT_SHARED", ROOT.parent / "shared")) / "data"


def read_stats(path: Path) -> dict[str, dict[str, float]]:
    """A thesis stats table (stats_realistic.csv / stats_optimistic.csv) by building name."""
    with open(path, newline="", encoding="utf-8") as handle:
        rows = list(csv.DictReader(handle, skipinitialspace=True))
    return {r["dataset"].strip(): {k.strip(): float(v) for k, v in r.items()
                                   if k.strip() != "dataset"} for r in rows}


def theirs_summary(realistic: dict, optimistic: dict) -> list[str]:
    """Lines on the seed study's CV of ε_r and its D_odo over the buildings of both tables."""
    cv = np.array([r["rotError.mean.std"] / r["rotError.mean.mean"] for r in realistic.values()])
    cv_opt = np.array([r["rotError.mean.std"] / r["rotError.mean.mean"]
                       for r in optimistic.values()])
    both = sorted(set(realistic) & set(optimistic))
    rot = np.array([realistic[b]["totalRot"] for b in both])
    d_odo = np.array([(realistic[b]["rotError.mean.mean"] ** 2
                       - optimistic[b]["rotError.mean.mean"] ** 2) for b in both]) / rot
    rho = spearmanr(rot, d_odo)[0]
    q10, q25, q50, q75, q90 = np.percentile(d_odo, [10, 25, 50, 75, 90])
    return [
        f"seed study, {len(realistic)} buildings: CV of ε_r over runs, realistic median "
        f"{np.median(cv):.2f} (IQR {np.percentile(cv, 25):.2f}-{np.percentile(cv, 75):.2f}); "
        f"optimistic median {np.median(cv_opt):.2f}",
        f"seed study, {len(both)} buildings: D_odo median {q50:.2e} rad²/rad (IQR {q25:.2e}-"
        f"{q75:.2e}, 10-90 % {q10:.2e}-{q90:.2e}); Spearman with totalRot {rho:+.2f}",
    ]


def campaign_runs(folder: Path, min_coverage: float) -> dict[str, list[dict]]:
    """Run records of a campaign folder by building, runs under ``min_coverage`` left out."""
    runs: dict[str, list[dict]] = {}
    for path in sorted(folder.glob("*/run_*/run.json")):
        record = json.loads(path.read_text(encoding="utf-8"))
        if float(record.get("coverage", 1.0)) >= min_coverage:
            runs.setdefault(path.parent.parent.name, []).append(record)
    return runs


def ours_summary(folder: Path, min_coverage: float) -> str:
    """One line: our CV of ε_r (buildings with ≥ 2 runs) and how ε_r follows |b_θ|."""
    cvs, bias, relative = [], [], []
    for records in campaign_runs(folder, min_coverage).values():
        if len(records) < 2:
            continue
        rot = np.array([r["metric"]["rot_mean"] for r in records])
        cvs.append(rot.std(ddof=1) / rot.mean())
        relative += list(rot / rot.mean())
        bias += [abs(r["odometry_error"]["bias"][2]) for r in records]
    if not cvs:
        return f"{folder.name}: no building with 2 runs"
    models = {r["odometry_error"]["model"] for recs in campaign_runs(folder, min_coverage)
              .values() for r in recs}
    spread = np.ptp(bias) > 0
    follow = f"Spearman(|b_θ|, ε_r / building mean) {spearmanr(bias, relative)[0]:+.2f}" \
        if spread else "b_θ the same in every run"
    return (f"{folder.name} ({', '.join(sorted(models))}): {len(cvs)} buildings, "
            f"{len(relative)} runs; CV of ε_r median {np.median(cvs):.2f}; {follow}")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("campaigns", type=Path, nargs="*")
    parser.add_argument("--thesis-dir", type=Path, default=SHARED_DATA / "thesis")
    parser.add_argument("--min-coverage", type=float, default=MIN_COVERAGE)
    args = parser.parse_args(argv)
    realistic = args.thesis_dir / "stats_realistic.csv"
    optimistic = args.thesis_dir / "stats_optimistic.csv"
    if not (realistic.is_file() and optimistic.is_file()):
        print(f"bench_odometry_signature: thesis tables not found in {args.thesis_dir}",
              file=sys.stderr)
        return 2
    for line in theirs_summary(read_stats(realistic), read_stats(optimistic)):
        print(line)
    for folder in args.campaigns:
        print(ours_summary(folder, args.min_coverage))
    return 0


if __name__ == "__main__":
    sys.exit(main())
