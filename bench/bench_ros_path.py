"""The same small batch through the ROS graph and in-process: wall time of each.

    source setup.bash
    python bench/bench_ros_path.py [--world worlds/tiny.world] [--runs 1] [--max-sim-time 60]
                                   [--nav slam_predict] [--explore slam_predict] [--port 11499]

ROS path: ``roslaunch slam_predict batch_explore.launch`` (its own master on ``--port``), wall
time from the command to its exit (launch, runs, shutdown). In-process: the batch of
``slam_predict.collect.batch`` with the in-process episode, same worlds, runs, seeds and caps.
Prints one line per path: runs, sim time, wall time, sim/wall.
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


def capped_settings(args, folder: Path) -> Path:
    """config/collect.yaml with absolute component paths and the sim-time cap, for both paths."""
    import yaml

    data = yaml.safe_load((ROOT / "config" / "collect.yaml").read_text())
    for key in ("robot", "gmapping", "navigation", "explore"):
        data[key] = str((ROOT / "config" / data.get(key, ".")).resolve())
    data.setdefault("stop", {})["max_sim_time_s"] = float(args.max_sim_time)
    path = folder / "collect.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def ros_batch(args, out: Path, settings: Path) -> float:
    """Run batch_explore.launch; returns its wall time (s)."""
    env = {**os.environ, "ROS_MASTER_URI": f"http://localhost:{args.port}",
           "ROS_HOME": str(out.parent / "ros_home")}
    command = ["roslaunch", "-p", str(args.port), "slam_predict", "batch_explore.launch",
               f"worlds:={Path(args.world).resolve()}", f"runs:={args.runs}", f"out:={out}",
               f"settings:={settings}", f"nav:={args.nav}", f"explore:={args.explore}"]
    started = time.perf_counter()
    with open(out.parent / "roslaunch.log", "w") as log:
        subprocess.run(command, env=env, stdout=log, stderr=subprocess.STDOUT, check=False,
                       timeout=args.runs * (args.max_sim_time * 20 + 600))
    return time.perf_counter() - started


def in_process_batch(args, out: Path, settings: Path) -> float:
    """The in-process batch with the same settings; returns its wall time (s)."""
    from slam_predict.collect.batch import Batch, BatchConfig

    world = Path(args.world).resolve()
    batch = Batch({world.stem: str(world)}, out,
                  BatchConfig(runs=args.runs, progress=False,
                              options={"settings": str(settings)}))
    started = time.perf_counter()
    batch.run()
    return time.perf_counter() - started


def report(name: str, out: Path, wall: float) -> None:
    records = [json.loads(p.read_text()) for p in sorted(out.glob("*/run_*/run.json"))]
    sim = sum(r["sim_duration_s"] for r in records)
    print(f"{name:11s} runs {len(records)}  sim {sim:7.1f} s  wall {wall:7.1f} s  "
          f"sim/wall {sim / wall if wall else float('nan'):5.2f}  "
          f"stop {[r['stop_reason'] for r in records]}", flush=True)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--world", default=str(ROOT / "worlds" / "tiny.world"))
    parser.add_argument("--runs", type=int, default=1)
    parser.add_argument("--max-sim-time", type=float, default=60.0)
    parser.add_argument("--nav", default="slam_predict")
    parser.add_argument("--explore", default="slam_predict")
    parser.add_argument("--port", type=int, default=11499)
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="bench_ros_path_") as tmp:
        settings = capped_settings(args, Path(tmp))
        ros_out, local_out = Path(tmp) / "ros", Path(tmp) / "local"
        report("ROS graph", ros_out, ros_batch(args, ros_out, settings))
        report("in-process", local_out, in_process_batch(args, local_out, settings))
    return 0


if __name__ == "__main__":
    sys.exit(main())
