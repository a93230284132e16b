#!/usr/bin/env python3
"""How far apart run-to-run noise alone puts our campaign's and the seed study's mean ε_t.

For every building of the campaign that the seed study's table holds: the relative standard
error of each side's mean (ours: the sample std of our per-run means over √n runs; theirs:
the table's ``transError.mean.std`` over √10, the fewest runs the seed study made per building,
so an upper bound), and the median over buildings of |N(0, 1) · combined error| in seeded
draws: what two unbiased measurements of the same buildings would differ by. Printed beside
the campaign's actual median |ours − theirs| / theirs.

Usage: ``bench/bench_seed_study_noise_floor.py [--campaign DIR] [--thesis CSV] [--draws N]``.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
THEIR_MIN_RUNS = 10   # the seed study's pilot sample per building (seed thesis 4.2.2)


def parse_args(argv=None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--campaign", default=str(ROOT / "data" / "campaigns"
                                                  / "fidelity_seed_study"))
    parser.add_argument("--thesis", default=str(ROOT.parent / "shared" / "data" / "thesis"
                                                / "stats_realistic.csv"))
    parser.add_argument("--draws", type=int, default=2000)
    return parser.parse_args(argv)


def relative_errors(campaign: Path, thesis: Path) -> tuple[np.ndarray, np.ndarray,
                                                           np.ndarray, np.ndarray]:
    """Per building with ≥ 2 runs: (|ours − theirs| / theirs, our spread / mean, their spread /
    mean, combined standard error / theirs)."""
    from slam_predict.collect.fidelity import compare_campaign, read_thesis_table

    table = read_thesis_table(thesis)
    comparison = compare_campaign(campaign, table)
    gap, ours_cv, theirs_cv, combined = [], [], [], []
    for row in comparison.rows:
        runs = comparison.per_run[row["world"]]["trans_mean"]
        if len(runs) < 2:
            continue
        theirs = table[row["world"]]
        mean, spread = float(np.mean(runs)), float(np.std(runs, ddof=1))
        gap.append(abs(mean - theirs["trans_mean"]) / theirs["trans_mean"])
        ours_cv.append(spread / mean)
        theirs_cv.append(theirs["trans_std"] / theirs["trans_mean"])
        combined.append(np.hypot(spread / np.sqrt(len(runs)),
                                 theirs["trans_std"] / np.sqrt(THEIR_MIN_RUNS))
                        / theirs["trans_mean"])
    return tuple(np.array(v) for v in (gap, ours_cv, theirs_cv, combined))


def main(argv=None) -> int:
    args = parse_args(argv)
    gap, ours_cv, theirs_cv, combined = relative_errors(Path(args.campaign), Path(args.thesis))
    rng = np.random.default_rng(0)
    draws = [float(np.median(np.abs(rng.normal(size=len(combined)) * combined)))
             for _ in range(args.draws)]
    low, mid, high = np.percentile(draws, [5, 50, 95])
    print(f"{len(gap)} buildings with >= 2 runs")
    print(f"run-to-run spread of the per-run mean eps_t (median over buildings): ours "
          f"{100 * np.median(ours_cv):.1f} %, theirs {100 * np.median(theirs_cv):.1f} %")
    print(f"noise alone: median |ours - theirs| / theirs {100 * mid:.1f} % "
          f"(90 % of draws {100 * low:.1f}-{100 * high:.1f} %)")
    print(f"measured: {100 * np.median(gap):.1f} %")
    return 0


if __name__ == "__main__":
    sys.exit(main())
