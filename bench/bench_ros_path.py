"""The same small batch through the ROS graph and in-process: wall time of each.

    source setup.bash
    python bench/bench_ros_path.py [--world worlds/tiny.world] [--runs 2] [--max-sim-time 120]
                                   [--nav slam_predict] [--explore slam_predict] [--port 11499]

ROS path: ``roslaunch slam_predict batch_explore.launch`` (its own master on ``--port``; the
full graph in lockstep), wall time from the command to its exit (launch, runs, shutdown).
In-process: ``slam-predict collect`` with the same world, runs, seeds and settings file (both
capped at ``--max-sim-time``). Prints one line per path: runs, sim time, wall time, sim/wall,
distance and coverage per run, stop reasons; and the load average before and after (the figures
mean little on a machine busy with other jobs).
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
    for key in ("robot", "navigation", "explore"):
        data[key] = str((ROOT / "config" / data.get(key, ".")).resolve())
    data["slam"]["params"] = str((ROOT / "config" / data["slam"]["params"]).resolve())
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
    """``slam-predict collect`` with the same settings; returns its wall time (s)."""
    command = [sys.executable, "-m", "slam_predict.cli.main", "collect",
               str(Path(args.world).resolve()), "--runs", str(args.runs), "--out", str(out),
               "--settings", str(settings), "--no-progress"]
    started = time.perf_counter()
    with open(out.parent / "collect.log", "w") as log:
        subprocess.run(command, stdout=log, stderr=subprocess.STDOUT, check=False,
                       timeout=args.runs * (args.max_sim_time * 20 + 600))
    return time.perf_counter() - started


def report(name: str, out: Path, wall: float) -> None:
    records = [json.loads(p.read_text()) for p in sorted(out.glob("*/run_*/run.json"))]
    sim = sum(r["sim_duration_s"] for r in records)
    print(f"{name:11s} runs {len(records)}  sim {sim:7.1f} s  wall {wall:7.1f} s  "
          f"sim/wall {sim / wall if wall else float('nan'):5.2f}  "
          f"distance {[round(r['distance_m'], 1) for r in records]} m  "
          f"coverage {[round(r['coverage'] or 0.0, 2) for r in records]}  "
          f"stop {[r['stop_reason'] for r in records]}", flush=True)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--world", default=str(ROOT / "worlds" / "tiny.world"))
    parser.add_argument("--runs", type=int, default=2)
    parser.add_argument("--max-sim-time", type=float, default=120.0)
    parser.add_argument("--nav", default="slam_predict")
    parser.add_argument("--explore", default="slam_predict")
    parser.add_argument("--port", type=int, default=11499)
    args = parser.parse_args(argv)
    print(f"load average before: {os.getloadavg()[0]:.1f}", flush=True)
    with tempfile.TemporaryDirectory(prefix="bench_ros_path_") as tmp:
        settings = capped_settings(args, Path(tmp))
        ros_out, local_out = Path(tmp) / "ros", Path(tmp) / "local"
        report("ROS graph", ros_out, ros_batch(args, ros_out, settings))
        print(f"load average: {os.getloadavg()[0]:.1f}", flush=True)
        report("in-process", local_out, in_process_batch(args, local_out, settings))
    print(f"load average after: {os.getloadavg()[0]:.1f}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
