"""Speed of the file formats and the relation metric; prints one figure per line.

Usage: .venv/bin/python bench/bench_metric.py [--shared ../shared]
"""
from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

import numpy as np

from slam_predict.formats.carmen import read_log, write_log
from slam_predict.formats.tum import read_tum, write_tum
from slam_predict.metric import (
    associate,
    evaluate_against_reference,
    evaluate_all_pairs,
    evaluate_sampled,
)


def timed(label: str, func, repeat: int = 3):
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        out = func()
        best = min(best, time.perf_counter() - start)
    print(f"{label}: {best:.3f} s")
    return out, best


def walk(rng, n):
    yaw = np.cumsum(rng.normal(0, 0.05, n))
    step = rng.uniform(0, 0.1, n)
    return np.column_stack([np.cumsum(step * np.cos(yaw)), np.cumsum(step * np.sin(yaw)), yaw])


def drift(rng, poses):
    return poses + np.cumsum(rng.normal(0, [0.003, 0.003, 0.0005], poses.shape), axis=0)


def bench_formats(shared: Path) -> None:
    log_path = shared / "data" / "slam_inputs" / "freiburg-079.log.gz"
    if not log_path.exists():
        print(f"skipping CARMEN figures: {log_path} not found")
        return
    log, _ = timed("read_log freiburg-079 (4791 FLASER x 360 + 4791 ODOM, gzip)",
                   lambda: read_log(log_path))
    with tempfile.TemporaryDirectory() as tmp:
        timed("write_log freiburg-079 (plain text)",
              lambda: write_log(os.path.join(tmp, "a.log"), log))
        timed("write_log freiburg-079 (gzip)",
              lambda: write_log(os.path.join(tmp, "a.log.gz"), log), 1)
        rng = np.random.default_rng(0)
        t = np.arange(60_000) * 0.1
        poses = walk(rng, 60_000)
        tum = os.path.join(tmp, "a.tum")
        timed("write_tum 60,000 poses", lambda: write_tum(tum, t, poses))
        timed("read_tum 60,000 poses", lambda: read_tum(tum))


def bench_metric() -> None:
    rng = np.random.default_rng(1)
    # Thesis §4.2.3: 1,500 m² office, 25 min at 10 Hz → 15,600 poses (243 M relations).
    ref = walk(rng, 15_600)
    est = drift(rng, ref)
    timed("yardstick: 5,000 random forward pairs on 15,600 poses",
          lambda: evaluate_against_reference(est, ref, 5000, 0), 5)
    result, _ = timed("thesis sampling (pilot 500 + sample size) on 15,600 poses",
                      lambda: evaluate_sampled(est, ref, np.random.default_rng(0)), 1)
    print(f"  -> sampled relations: {result.n_relations}")
    n = 5000
    _, secs = timed(f"all forward pairs on {n} poses ({n * (n - 1) // 2:,} relations)",
                    lambda: evaluate_all_pairs(est[:n], ref[:n]), 1)
    rate = n * (n - 1) / 2 / secs
    print(f"  -> {rate / 1e6:.1f} M relations/s; "
          f"all 243 M pairs of 15,600 poses ≈ {243e6 / rate:.0f} s")
    t_a = np.sort(rng.uniform(0, 6000, 60_000))
    t_b = np.sort(t_a + rng.normal(0, 0.003, 60_000))
    timed("associate 60,000 x 60,000 stamps", lambda: associate(t_a, t_b, 0.01))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--shared", default=str(Path(__file__).resolve().parents[2] / "shared"))
    args = parser.parse_args()
    bench_formats(Path(args.shared))
    bench_metric()


if __name__ == "__main__":
    main()
