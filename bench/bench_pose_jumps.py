"""Where a campaign's online SLAM pose jumps: the loop closures that move the robot by metres.

For every run of a campaign folder (``WORLD/run_NNN/``) this reads the online pose
(``slam.tum``: map → base_link at 10 Hz) and the ground truth (``ground_truth.tum``), puts the
map frame on the true start pose (both start at the same place), and reports the online
position error over time and every step of 0.1 s in which it changes by more than
``--jump`` m (default 0.3). Sequential scan matching cannot move the pose that far in one step
(Karto's search window is ±0.25 m, GMapping's hill climbing a few cm), so such a step is a pose
graph (or particle) correction: for Karto, a loop closure. A jump that raises the error is a
closure that put the robot where it is not; one that lowers it, a closure that mends an error.

    python bench/bench_pose_jumps.py data/campaigns/karto_seed_study [--jump 0.3] [--csv OUT]

Per run: coverage, the largest error before the first jump, the first jump that raises the
error (time, error before → after), the error at the end; then how many runs that end below
coverage 0.95 had such a jump first.
"""
from __future__ import annotations

import argparse
import csv
import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from slam_predict.collect.fidelity_parts import FULL_COVERAGE  # noqa: E402
from slam_predict.formats.tum import read_tum  # noqa: E402
from slam_predict.geometry import compose  # noqa: E402


def online_error(run: Path) -> tuple[np.ndarray, np.ndarray]:
    """(t s, online position error m) of one run: slam.tum in the frame of the true start."""
    t_true, true = read_tum(run / "ground_truth.tum")
    t_slam, slam = read_tum(run / "slam.tum")
    n = min(len(t_true), len(t_slam))
    if not np.allclose(t_true[:n], t_slam[:n], atol=1e-6):
        raise SystemExit(f"{run}: ground_truth.tum and slam.tum have other time stamps")
    placed = compose(true[0], slam[:n])
    return t_true[:n], np.hypot(*(placed[:, :2] - true[:n, :2]).T)


def run_row(run: Path, jump_m: float) -> dict:
    """The report row of one run (module doc)."""
    record = json.loads((run / "run.json").read_text())
    t, error = online_error(run)
    steps = np.flatnonzero(np.abs(np.diff(error)) > jump_m)
    raising = [i for i in steps if error[i + 1] > error[i]]
    first = raising[0] if raising else None
    before = error[: first + 1] if first is not None else error
    return {"world": record["world"], "run": run.name, "coverage": record["coverage"],
            "stop_reason": record["stop_reason"], "jumps": len(steps),
            "max_error_before_m": float(before.max()),
            "first_raising_jump_s": float(t[first + 1]) if first is not None else "",
            "jump_from_m": float(error[first]) if first is not None else "",
            "jump_to_m": float(error[first + 1]) if first is not None else "",
            "final_error_m": float(error[-1])}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("campaign", type=Path)
    parser.add_argument("--jump", type=float, default=0.3, help="jump threshold per 0.1 s, m")
    parser.add_argument("--csv", type=Path, help="also write the rows here")
    args = parser.parse_args(argv)
    runs = [record.parent for record in sorted(args.campaign.glob("*/run_*/run.json"))]
    kept = [run for run in runs if (run / "slam.tum").is_file()
            and (run / "ground_truth.tum").is_file()]
    if len(kept) < len(runs):
        print(f"{len(runs) - len(kept)} of {len(runs)} runs have no trajectories here "
              "(only run.json is committed): skipped")
    rows = [run_row(run, args.jump) for run in kept]
    for r in rows:
        jump = (f"first raising jump at {r['first_raising_jump_s']:.1f} s: "
                f"{r['jump_from_m']:.2f} → {r['jump_to_m']:.2f} m"
                if r["first_raising_jump_s"] != "" else "no raising jump")
        print(f"{r['world'][:28]:28s} {r['run']} coverage {r['coverage']:.3f}  max error "
              f"before {r['max_error_before_m']:.2f} m  {jump}  end {r['final_error_m']:.2f} m")
    low = [r for r in rows if r["coverage"] < FULL_COVERAGE]
    low_jump = [r for r in low if r["first_raising_jump_s"] != ""]
    full_jump = [r for r in rows if r["coverage"] >= FULL_COVERAGE
                 and r["first_raising_jump_s"] != ""]
    print(f"{len(rows)} runs; {len(low)} below coverage {FULL_COVERAGE}, {len(low_jump)} of "
          f"them with a raising jump > {args.jump} m; {len(rows) - len(low)} at or above it, "
          f"{len(full_jump)} of them with one")
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
