#!/usr/bin/env python3
"""Benchmark of ``slam-predict predict`` end to end (target: a 1,500 m² plan in ≤ 3 s, warm).

Runs the real command in fresh processes, as a user would:

* cold: an empty numba cache (``NUMBA_CACHE_DIR`` in a new temporary folder) — every kernel is
  compiled during the run;
* warm: the same cache again, now filled — the state after ``make setup``.

Then, in this process (warm), the split between loading the plan, computing the features and
evaluating the models; then (warm) ``predict --slam karto`` and ``predict --compare gmapping
karto`` against a Karto model: no Karto model ships, so the bench labels a copy of the GMapping
model ``slam: karto`` in a temporary folder named by ``$SLAM_PREDICT_MODELS`` (the same target:
the Karto model is another model folder, Karto itself never runs). Times are wall and CPU
(the child process's user + system) seconds. Usage:
``bench/bench_predict.py [PLAN] [--resolution R] [--model NAME] [--setting S] [--repeat N]``.
"""
from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_PLAN = ROOT / "worlds" / "office_1500.world"


def child_cpu() -> float:
    """CPU seconds (user + system) of the finished child processes so far."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_cli(plan: str, model: str, setting: str, cache: str,
            resolution: float | None = None, extra: tuple = (), models: str | None = None):
    """(wall time s, CPU time s, parsed JSON) of one ``slam-predict predict --json`` process
    (``extra``: more options; ``models``: ``$SLAM_PREDICT_MODELS``)."""
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    if models is not None:
        env["SLAM_PREDICT_MODELS"] = models
    cmd = [sys.executable, "-m", "slam_predict.cli.main", "predict", plan, "--json", *extra]
    if not extra:
        cmd += ["--model", model, "--thesis-setting", setting]
    if resolution is not None:
        cmd += ["--resolution", str(resolution)]
    cpu = child_cpu()
    start = time.perf_counter()
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True, check=False)
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        sys.exit(f"predict failed ({proc.returncode}): {proc.stderr.strip()}")
    return wall, child_cpu() - cpu, json.loads(proc.stdout)


def karto_cases(args, cache: str, model_store: str) -> None:
    """``--slam karto`` and ``--compare gmapping karto``, warm, with the GMapping model
    ``model_store`` labelled Karto in a temporary ``$SLAM_PREDICT_MODELS`` folder."""
    from slam_predict.learn.store import default_models_dir

    with tempfile.TemporaryDirectory(prefix="karto_models_") as folder:
        target = Path(folder) / f"{model_store}-as-karto"
        shutil.copytree(default_models_dir() / model_store, target)
        card = json.loads((target / "card.json").read_text())
        (target / "card.json").write_text(json.dumps({**card, "slam": "karto",
                                                      "name": target.name}))
        for label, extra in (("--slam karto", ("--slam", "karto")),
                             ("--compare gmapping karto", ("--compare", "gmapping", "karto"))):
            runs = [run_cli(args.plan, args.model, args.setting, cache, args.resolution, extra,
                            folder) for _ in range(args.repeat)]
            best = min(runs, key=lambda r: r[0])
            print(f"{label}, warm: {best[0]:.2f} s wall, {best[1]:.2f} s CPU (best of "
                  f"{args.repeat}, worst {max(r[0] for r in runs):.2f} s wall; target ≤ 3 s)")
        verdict = best[2]["decision"]
        print(f"  the call: {verdict['verdict']} (probability {verdict['probability']})")


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
        cold, cold_cpu, result = run_cli(args.plan, args.model, args.setting, cache,
                                         args.resolution)
        warm_runs = [run_cli(args.plan, args.model, args.setting, cache, args.resolution)[:2]
                     for _ in range(args.repeat)]
        warm, warm_cpu = min(warm_runs)
        split = breakdown(args.plan, args.model, args.resolution)
        print(f"plan: {args.plan} ({split['free_area_m2']:.0f} m² free), model "
              f"{result['model_store']}")
        print(f"end to end, cold numba cache: {cold:.2f} s wall, {cold_cpu:.2f} s CPU")
        print(f"end to end, warm numba cache: {warm:.2f} s wall, {warm_cpu:.2f} s CPU (best of "
              f"{args.repeat}, worst {max(w for w, _ in warm_runs):.2f} s wall; target ≤ 3 s)")
        print(f"in-process (warm): load {split['load']:.2f} s, features "
              f"{split['features']:.2f} s, models {split['models']:.3f} s")
        karto_cases(args, cache, result["model_store"])
    print(f"load average (1 min) at the end: {os.getloadavg()[0]:.1f}")
    entry = result["trans_mean"]
    if entry["status"] != "ok" or entry["low"] is None:
        print(f"trans_mean: {entry['status']} (raw output {entry.get('raw_value')})")
    else:
        print(f"trans_mean {entry['value']:.3f} m [{entry['low']:.3f}, {entry['high']:.3f}]")


if __name__ == "__main__":
    main()
