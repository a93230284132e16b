#!/usr/bin/env python3
"""What the real slam_gmapping spends per scan and per map rebuild (CPU s), measured on the
sensor logs of collected runs: the calibration of the compute-delay model (`slam_compute` in
collect settings, src/slam_predict/slam/compute_delay.py; docs/fidelity.md).

The real openslam_gmapping, built outside the repository with bench/gmapping_diff/build.sh,
replays each run's sensors.log.gz with the run's recorded GMapping parameters; its driver times
(process CPU time) every processScan and, as slam_gmapping's updateMap does after a processed
scan more than map_update_interval past the last rebuild, a rebuild of the map from the best
particle's whole trajectory. Printed per run: scans, processed scans, processScan CPU s (mean,
median, 90th percentile), the least-squares fit rebuild_s = fixed + per_cell × traced beam cells,
the last rebuild; then the `slam_compute` values the fits give (medians over runs).

Usage: bench/bench_gmapping_compute.py --build BUILD_DIR RUN_OR_CAMPAIGN_DIR... [--seed 1]
"""
from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
sys.path.insert(0, str(ROOT / "bench" / "gmapping_diff"))

from collected_runs import SENSOR_LOG, find_runs, recorded_params, run_name  # noqa: E402


def time_run(folder: Path, driver: Path, seed: int) -> dict:
    """Replay one run's sensor log through the real library with timing on."""
    from slam_predict import slam
    from slam_predict.formats.prepared_scans import write_prepared_scans
    from slam_predict.slam.gmapping.params import with_ranges
    from slam_predict.slam.runner import read_input

    data = read_input(folder / SENSOR_LOG)
    params = slam.params_from_dict("gmapping", recorded_params(folder), str(folder))
    with tempfile.TemporaryDirectory() as tmp:
        scans, traj, timing = (Path(tmp) / n for n in ("scans.txt", "out.traj", "timing.txt"))
        angle_mode = "node" if params.range_sensor_angles else "exact"
        write_prepared_scans(scans, data.times, data.odometry, data.ranges, data.laser,
                             with_ranges(params, data.laser.range_max), seed, angle_mode)
        subprocess.run([str(driver), str(scans), str(traj), str(timing)], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        rows = np.loadtxt(timing, ndmin=2)
    rebuilds = rows[rows[:, 3] > 0]
    design = np.c_[np.ones(len(rebuilds)), rebuilds[:, 5]]
    (fixed, per_cell), *_ = np.linalg.lstsq(design, rebuilds[:, 3], rcond=None)
    return {"run": run_name(folder), "scans": len(data), "processed": len(rows),
            "particles": params.particles, "beams": int(data.ranges.shape[1]),
            "process_s": rows[:, 2], "fixed_s": float(fixed), "per_cell_s": float(per_cell),
            "map_cells": float(rebuilds[0, 6]), "last_rebuild_s": float(rebuilds[-1, 3]),
            "last_nodes": int(rebuilds[-1, 4]), "last_cells": float(rebuilds[-1, 5])}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", help="collected run folders or campaigns")
    parser.add_argument("--build", required=True, type=Path,
                        help="BUILD_DIR of bench/gmapping_diff/build.sh (has the driver)")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    driver = args.build / "gmapping_diff_driver"
    if not driver.is_file():
        raise SystemExit(f"{driver}: missing; run bench/gmapping_diff/build.sh first")
    results = [time_run(folder, driver, args.seed) for folder in find_runs(args.runs)]
    print("| run | scans | processed | particles × beams | processScan CPU s mean / median / "
          "p90 | rebuild fixed s | rebuild ns per beam cell | last rebuild s (nodes, M cells) |")
    print("|" + "---|" * 8)
    for r in results:
        p = r["process_s"]
        print(f"| {r['run']} | {r['scans']} | {r['processed']} | {r['particles']} × {r['beams']} "
              f"| {p.mean():.3f} / {np.median(p):.3f} / {np.percentile(p, 90):.3f} "
              f"| {r['fixed_s']:.3f} | {r['per_cell_s'] * 1e9:.1f} "
              f"| {r['last_rebuild_s']:.2f} ({r['last_nodes']}, {r['last_cells'] / 1e6:.1f}) |")
    scan_s = float(np.median([np.mean(r["process_s"]) for r in results]))
    per_map = float(np.median([r["fixed_s"] / r["map_cells"] for r in results]))
    per_line = float(np.median([r["per_cell_s"] for r in results]))
    print(f"\nslam_compute (this machine, cpu_factor 1): scan_s {scan_s:.4g}, "
          f"rebuild_s_per_map_cell {per_map:.4g}, rebuild_s_per_line_cell {per_line:.4g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
