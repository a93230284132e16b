"""GMapping benchmark: our port against the real openslam_gmapping on the shared real-robot logs.

For each log (intel, aces, csail, freiburg-101 by default) and seed, runs
``slam-predict slam run LOG --config ../shared/baselines/gmapping_real_<log>.yaml --seed S`` in its
own process (so CPU time and peak RSS are per run, numba cache warm) and prints, next to the
baseline of ../shared/baselines/gmapping_real.json: the mean relative translational error over
seeds (5,000 random forward pairs, pair seed 0), its median and range, the rotational error, the
raw odometry's error, CPU time and peak RSS. Then the acceptance figures: mean over logs of
(ours / real GMapping) ≤ 1.25 and ours ≤ 0.25 × odometry on every log.

``--memory`` instead runs 40 particles with config/gmapping.yaml (the thesis settings) on a
simulated ~5,800 m² building (ipa lab_a at the thesis' 0.1 m/px), laser 270°/0.5°, and reports
the peak RSS (target ≤ 1.5 GB).

Usage: bench/bench_gmapping.py [--seeds 1-10] [--logs intel aces] [--jobs 1] [--out DIR]
       bench/bench_gmapping.py --memory
Results of finished runs are kept in DIR (default out/bench_gmapping) and reused.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("SLAM_PREDICT_SHARED", ROOT.parent / "shared"))
LOGS = ("intel", "aces", "csail", "freiburg-101")


def seeds_arg(text: str):
    if "-" in text:
        lo, hi = text.split("-")
        return list(range(int(lo), int(hi) + 1))
    return [int(v) for v in text.split(",")]


def run_one(log: str, seed: int, out: Path) -> dict:
    """One run in a subprocess; cached in out/<log>_<seed>/stats.json."""
    folder = out / f"{log}_{seed}"
    stats = folder / "stats.json"
    if not stats.exists():
        cmd = [sys.executable, "-m", "slam_predict.cli.main", "slam", "run",
               str(SHARED / "data" / "slam_inputs" / f"{log}.log.gz"),
               "--config", str(SHARED / "baselines" / f"gmapping_real_{log}.yaml"),
               "--seed", str(seed), "--out", str(folder)]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return json.loads(stats.read_text())


def table(results: dict, baseline: dict) -> str:
    head = ("| log | scans processed | trans mean (m) | median | min–max | rot mean (deg) | CPU s "
            "| peak RSS MiB | odometry (m) | real GMapping trans mean (m) | ratio | real CPU s |")
    lines = [head, "|" + "---|" * 12]
    ratios = []
    ok_odo = True
    for log, runs in results.items():
        trans = np.array([r["evaluation"]["slam"]["trans_mean_m"] for r in runs])
        rot = np.array([r["evaluation"]["slam"]["rot_mean_deg"] for r in runs])
        odo = float(np.mean([r["evaluation"]["odometry"]["trans_mean_m"] for r in runs]))
        cpu = float(np.mean([r["cpu_s"] for r in runs]))
        rss = float(np.max([r["peak_rss_mib"] for r in runs]))
        base = baseline[log]
        ratio = trans.mean() / base["trans_mean_over_seeds_m"]
        ratios.append(ratio)
        ok_odo &= trans.mean() <= 0.25 * odo
        lines.append(
            f"| {log} | {runs[0]['scans_processed']} / {runs[0]['input_info']['scans_in_log']} "
            f"| {trans.mean():.3f} | {np.median(trans):.3f} | {trans.min():.3f}–{trans.max():.3f} "
            f"| {rot.mean():.2f} | {cpu:.1f} | {rss:.0f} | {odo:.1f} "
            f"| {base['trans_mean_over_seeds_m']:.3f} | {ratio:.2f} "
            f"| {np.mean(base['cpu_s']):.1f} |")
    seeds = len(next(iter(results.values())))
    lines.append("")
    lines.append(f"Seeds per log: {seeds}. Mean ratio over logs: {np.mean(ratios):.3f} "
                 f"(target ≤ 1.25: {'PASS' if np.mean(ratios) <= 1.25 else 'FAIL'}); "
                 f"ours ≤ 0.25 × odometry on every log: {'PASS' if ok_odo else 'FAIL'}.")
    return "\n".join(lines)


def real_logs(args) -> None:
    baseline = json.loads((SHARED / "baselines" / "gmapping_real.json").read_text())
    out = Path(args.out)
    jobs = [(log, seed) for log in args.logs for seed in args.seeds]
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        done = list(pool.map(lambda job: run_one(job[0], job[1], out), jobs))
    results: dict = {}
    for (log, _), stats in zip(jobs, done, strict=False):
        results.setdefault(log, []).append(stats)
    print(table(results, baseline))
    for log in args.logs:
        png = out / f"{log}_{args.seeds[0]}" / "map.png"
        if png.exists() and args.docs:
            target = ROOT / "docs" / f"gmapping_{log}.png"
            target.write_bytes(png.read_bytes())
            print(f"map of {log} (seed {args.seeds[0]}) -> {target.relative_to(ROOT)}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--logs", nargs="+", default=list(LOGS))
    parser.add_argument("--seeds", type=seeds_arg, default=list(range(1, 11)))
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--out", default=str(ROOT / "out" / "bench_gmapping"))
    parser.add_argument("--docs", action="store_true", help="copy the seed's map PNGs to docs/")
    parser.add_argument("--memory", action="store_true", help="the 40-particle memory benchmark")
    args = parser.parse_args()
    if args.memory:
        sys.path.insert(0, str(ROOT / "bench"))
        from gmapping_memory import main as memory_main

        memory_main()
        return
    real_logs(args)


if __name__ == "__main__":
    main()
