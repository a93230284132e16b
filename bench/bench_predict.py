#!/usr/bin/env python3
"""Benchmark of ``slam-predict predict`` end to end (target: a 1,500 m² plan in ≤ 3 s, warm).

Runs the real command in fresh processes, as a user would:

* cold: an empty numba cache (``NUMBA_CACHE_DIR`` in a new temporary folder) — every kernel is
  compiled during the run;
* warm: the same cache again, now filled — the state after ``make setup``.

Then, in this process (warm), the split between loading the plan, computing the features and
evaluating the models. Usage:
``bench/bench_predict.py [PLAN] [--resolution R] [--model NAME] [--setting S] [--repeat N]``.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_PLAN = ROOT / "worlds" / "office_1500.world"


def run_cli(plan: str, model: str, setting: str, cache: str,
            resolution: float | None = None) -> tuple:
    """(wall time s, parsed JSON) of one ``slam-predict predict --json`` process."""
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    cmd = [sys.executable, "-m", "slam_predict.cli.main", "predict", plan, "--model", model,
           "--thesis-setting", setting, "--json"]
    if resolution is not None:
        cmd += ["--resolution", str(resolution)]
    start = time.perf_counter()
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True, check=False)
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        sys.exit(f"predict failed ({proc.returncode}): {proc.stderr.strip()}")
    return wall, json.loads(proc.stdout)


def breakdown(plan: str, model: str, resolution: float | None = None) -> dict:
    """Seconds spent loading, computing features and predicting, in this (warm) process."""
    from slam_predict.features.plan import compute
    from slam_predict.learn.model import resolve_store
    from slam_predict.learn.predict import check_feature_version, predict_features
    from slam_predict.learn.store import default_models_dir
    from slam_predict.world.load import load_plan

    t0 = time.perf_counter()
    world = load_plan(plan, resolution=resolution)
    t1 = time.perf_counter()
    store = resolve_store(default_models_dir(), model, None, None)
    check_feature_version(store)
    features = compute(world, store.card.get("feature_config") or {})
    t2 = time.perf_counter()
    predict_features(features, store)
    t3 = time.perf_counter()
    return {"load": t1 - t0, "features": t2 - t1, "models": t3 - t2,
            "free_area_m2": world.free_area_m2}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("plan", nargs="?", default=str(DEFAULT_PLAN))
    parser.add_argument("--model", default="best")
    parser.add_argument("--thesis-setting", dest="setting", default="realistic")
    parser.add_argument("--resolution", type=float, default=None,
                        help="m/px, for an image without a map_server YAML")
    parser.add_argument("--repeat", type=int, default=3, help="warm runs (best is reported)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="numba_cold_") as cache:
        cold, result = run_cli(args.plan, args.model, args.setting, cache, args.resolution)
        warm_runs = [run_cli(args.plan, args.model, args.setting, cache, args.resolution)[0]
                     for _ in range(args.repeat)]
    warm = min(warm_runs)
    split = breakdown(args.plan, args.model, args.resolution)
    print(f"plan: {args.plan} ({split['free_area_m2']:.0f} m² free), model "
          f"{result['model_store']}")
    print(f"end to end, cold numba cache: {cold:.2f} s")
    print(f"end to end, warm numba cache: {warm:.2f} s (best of {args.repeat}, worst "
          f"{max(warm_runs):.2f} s; target ≤ 3 s)")
    print(f"in-process (warm): load {split['load']:.2f} s, features {split['features']:.2f} s, "
          f"models {split['models']:.3f} s")
    print(f"load average (1 min) at the end: {os.getloadavg()[0]:.1f}")
    entry = result["trans_mean"]
    if entry["status"] != "ok" or entry["low"] is None:
        print(f"trans_mean: {entry['status']} (raw output {entry.get('raw_value')})")
    else:
        print(f"trans_mean {entry['value']:.3f} m [{entry['low']:.3f}, {entry['high']:.3f}]")


if __name__ == "__main__":
    main()
