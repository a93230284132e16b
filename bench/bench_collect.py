"""Batch throughput of ``slam-predict collect`` on this machine: the same batch with 1 and 2 jobs.

    source setup.bash
    python bench/bench_collect.py [--worlds worlds/tiny.world worlds/office_150.world]
                                  [--runs 2] [--jobs 1 2]

Each batch is a fresh ``slam-predict collect`` campaign (GMapping in the loop, config/collect.yaml,
numba cache warm) in a temporary folder. Prints per job count: runs, wall time, runs per hour,
simulated seconds per wall second, the speed-up over one job, one line per run (stop reason,
coverage of the reachable free area, stalls, error), and the load average before and after
(figures mean little on a machine busy with other jobs). Issue #7's coverage benchmark:
``--worlds`` every shipped world up to 1,500 m², ``--runs 1 --jobs 2``.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def run_batch(worlds, runs: int, jobs: int, out: Path) -> dict:
    """One collect campaign; returns its wall time (s) and total simulated time (s)."""
    cmd = ["slam-predict", "collect", *worlds, "--runs", str(runs), "--jobs", str(jobs),
           "--out", str(out)]
    start = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - start
    records = [json.loads(p.read_text()) for p in sorted(out.glob("*/run_*/run.json"))]
    return {"wall": wall, "runs": len(records), "records": records,
            "sim": sum(r["sim_duration_s"] for r in records)}


def print_runs(records) -> None:
    """One line per run: world, free area, stop, sim and wall time, coverage, stalls, error."""
    print("| world | free m² | stop | explorer end | sim s | wall s | coverage | stalls | path m "
          "| trans_mean m |")
    print("|---|---:|---|---|---:|---:|---:|---:|---:|---:|")
    for r in sorted(records, key=lambda r: r["free_area_m2"]):
        end = (r.get("explorer_end") or {}).get("reason", "-")
        print(f"| {r['world']} | {r['free_area_m2']:.0f} | {r['stop_reason']} | {end} "
              f"| {r['sim_duration_s']:.0f} | {r['wall_time_s']:.0f} | {r['coverage']:.3f} "
              f"| {r['stalls']} | {r['distance_m']:.0f} | {r['metric']['trans_mean']:.3f} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--worlds", nargs="+",
                        default=[str(ROOT / "worlds" / "tiny.world"),
                                 str(ROOT / "worlds" / "office_150.world")])
    parser.add_argument("--runs", type=int, default=2, help="runs per world")
    parser.add_argument("--jobs", type=int, nargs="+", default=[1, 2])
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()[0]:.2f}, cores: {os.cpu_count()}")
    base = None
    with tempfile.TemporaryDirectory(prefix="bench_collect_") as tmp:
        for jobs in args.jobs:
            got = run_batch(args.worlds, args.runs, jobs, Path(tmp) / f"jobs{jobs}")
            rate = got["runs"] / got["wall"] * 3600.0
            base = base or got["wall"]
            print(f"jobs {jobs}: {got['runs']} runs in {got['wall']:.1f} s wall, "
                  f"{rate:.1f} runs/h, sim/wall {got['sim'] / got['wall']:.2f}, "
                  f"speed-up {base / got['wall']:.2f}x")
            print_runs(got["records"])
    print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
