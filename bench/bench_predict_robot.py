#!/usr/bin/env python3
"""Benchmark of ``slam-predict predict PLAN --robot FILE`` end to end (target, issue #18: a
1,500 m² plan in ≤ 3 s with a warm numba cache).

1. Trains a robot-aware model on the synthetic campaign of tests/learn/robot_synthetic.py
   into a temporary folder: the shipped learning configuration (config/robot_learning.yaml:
   elasticnet, 200-stage gradient boosting, Gaussian process), 21 buildings × 4
   configurations × 2 runs = the real campaign's 168 runs, the Gaussian process as best for
   the means and gradient boosting for the stds (the dearest to evaluate). Its numbers mean
   nothing for a real plan; the timing is what counts. ``--models-dir DIR`` reuses a folder.
2. Runs ``slam-predict predict PLAN --robot ROBOT --models-dir TMP --json`` in fresh
   processes (one untimed warm-up, then ``--repeat`` timed runs: best and worst).
3. Splits a warm run in a fresh process: loading the plan, computing the features and the
   sight-line curve (features/sightline.py), loading the model folder, predicting (with
   domain warnings), and whether scikit-learn or joblib got imported (they should not: the
   models are read from their plain-array forms).

Usage: ``bench/bench_predict_robot.py [PLAN] [--robot FILE] [--repeat N] [--models-dir DIR]``.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_PLAN = ROOT / "worlds" / "office_1500.world"
DEFAULT_ROBOT = ROOT / "config" / "robots" / "lds_360_3p5.yaml"
BEST = {"trans_mean": "gaussian_process", "rot_mean": "gaussian_process",
        "trans_std": "gradient_boosting", "rot_std": "gradient_boosting"}

SPLIT = """
import json, sys, time
t0 = time.perf_counter()
from slam_predict.world.load import load_plan
world = load_plan(sys.argv[1])
t1 = time.perf_counter()
from slam_predict.learn.robot.predict import RobotModel
model = RobotModel.load(sys.argv[3])
model.check_feature_version()
t2 = time.perf_counter()
from slam_predict.features.plan import compute
features = compute(world, model.feature_config)
t3a = time.perf_counter()
if model.sightline_config is not None:
    from slam_predict.features.sightline import SightlineConfig, sightline_features
    features.update(sightline_features(world, SightlineConfig(**model.sightline_config)))
t3 = time.perf_counter()
from slam_predict.learn.robot.inputs import angular_resolution_deg, sensor_dict
from slam_predict.robot_file import load_robot
robot = load_robot(sys.argv[2])
inputs = model.inputs(robot)
model.predict(features, inputs)
model.domain_warnings(features, inputs, angular_resolution_deg(sensor_dict(robot)))
t4 = time.perf_counter()
print(json.dumps({"load": t1 - t0, "model_load": t2 - t1, "features": t3a - t2,
                  "sightlines": t3 - t3a,
                  "predict": t4 - t3, "free_area_m2": world.free_area_m2,
                  "sklearn": sorted(m for m in sys.modules
                                    if m.split(".")[0] in ("sklearn", "joblib"))[:3]}))
"""


def train(folder: Path) -> tuple[Path, float]:
    """(models folder, training wall time s) of the synthetic robot-aware model."""
    sys.path.insert(0, str(ROOT / "tests" / "learn"))
    import robot_synthetic as syn

    from slam_predict.learn.robot.config import load_robot_learning_config

    config = load_robot_learning_config(ROOT / "config" / "robot_learning.yaml")
    start = time.perf_counter()
    syn.train_model(folder, "own-robots", config, BEST, n_worlds=21, n_configs=4)
    return folder / "models", time.perf_counter() - start


def command() -> list[str]:
    """The installed ``slam-predict`` console script, else ``python -m``."""
    script = shutil.which("slam-predict")
    return [script] if script else [sys.executable, "-m", "slam_predict.cli.main"]


def run_cli(plan: str, robot: str, models: Path) -> tuple[float, dict]:
    """(wall time s, parsed JSON) of one fresh ``slam-predict predict --robot`` process."""
    cmd = [*command(), "predict", plan, "--robot", robot, "--models-dir", str(models), "--json"]
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        sys.exit(f"predict failed ({proc.returncode}): {proc.stderr.strip()}")
    return wall, json.loads(proc.stdout)


def split(plan: str, robot: str, models: Path) -> dict:
    """Seconds per step of a warm run, in a fresh process."""
    proc = subprocess.run([sys.executable, "-c", SPLIT, plan, robot, str(models / "own-robots")],
                          capture_output=True, text=True, check=True)
    return json.loads(proc.stdout)


def report(args, models: Path, trained: float | None) -> None:
    run_cli(args.plan, args.robot, models)    # warm-up (numba cache, page cache)
    walls = []
    for _ in range(args.repeat):
        wall, result = run_cli(args.plan, args.robot, models)
        walls.append(wall)
    parts = split(args.plan, args.robot, models)
    if trained is not None:
        print(f"model trained on the synthetic campaign in {trained:.0f} s ({models})")
    print(f"plan: {args.plan} ({parts['free_area_m2']:.0f} m² free), robot {args.robot}, "
          f"model {result['model_store']} (best: "
          + ", ".join(f"{c} {result[c]['model'].split('/')[-1]}" for c in BEST) + ")")
    print(f"end to end, warm numba cache: best {min(walls):.2f} s, worst {max(walls):.2f} s "
          f"of {args.repeat} (target ≤ 3 s)")
    print(f"in-process split (warm, fresh process): load {parts['load']:.2f} s, model folder "
          f"{parts['model_load']:.2f} s, features {parts['features']:.2f} s, sight lines "
          f"{parts['sightlines']:.2f} s, predict "
          f"{1000 * parts['predict']:.1f} ms; scikit-learn/joblib imported: "
          f"{parts['sklearn'] or 'no'}")
    print(f"load average (1 min) at the end: {os.getloadavg()[0]:.1f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("plan", nargs="?", default=str(DEFAULT_PLAN))
    parser.add_argument("--robot", default=str(DEFAULT_ROBOT))
    parser.add_argument("--repeat", type=int, default=5, help="timed runs (default 5)")
    parser.add_argument("--models-dir", type=Path,
                        help="a models folder holding own-robots (default: train one)")
    args = parser.parse_args()
    if args.models_dir is not None:
        report(args, args.models_dir, None)
        return
    with tempfile.TemporaryDirectory(prefix="bench_predict_robot_") as tmp:
        models, trained = train(Path(tmp))
        report(args, models, trained)


if __name__ == "__main__":
    main()
