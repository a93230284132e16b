"""Sensor-log cost benchmark (issue #16): the time and bytes ``sensor_logs: true`` adds to a
collected run, and the replay of both logs.

Runs :func:`slam_predict.collect.episode.run_episode` on WORLD (default: the shipped office_150,
config/collect.yaml, sim time capped by ``--max-sim-time``) with sensor logs on and prints: the
sim time, distance driven, episode wall time, the recorder's own wall time (serialising and
writing both logs, run.json ``timing.sensor_logs``) and its share, the sizes of sensors.bag and
sensors.log.gz (total, per scan, per 100 m driven, per hour of sim time), then replays each log
with ``slam-predict slam run`` and prints its wall time and whether the replayed trajectory is
identical to the in-loop one (slam_scans.tum). ``--compare`` also runs the same episode with
sensor logs off and prints both wall times (noisy on a loaded machine).

Usage: bench/bench_sensor_logs.py [WORLD] [--max-sim-time S] [--seed N] [--particles N]
       [--compare]
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from slam_predict.cli.main import main as cli  # noqa: E402
from slam_predict.collect.batch import RunSpec  # noqa: E402
from slam_predict.collect.episode import run_episode  # noqa: E402
from slam_predict.collect.sensorlog import SENSOR_BAG, SENSOR_LOG, SLAM_SCANS  # noqa: E402
from slam_predict.collect.settings import load_settings  # noqa: E402
from slam_predict.warmup import warm_all  # noqa: E402


def episode(world: Path, out: Path, args, sensor_logs: bool) -> dict:
    settings = load_settings()
    settings.sensor_logs = sensor_logs
    settings.stop = dataclasses.replace(settings.stop, max_sim_time_s=args.max_sim_time)
    if args.particles:
        settings.slam.params = dataclasses.replace(settings.slam.params, particles=args.particles)
    spec = RunSpec(str(world), world.stem, 0, args.seed, str(out))
    cpu = time.process_time()
    record = run_episode(spec, settings)
    record["episode_cpu_s"] = time.process_time() - cpu
    return record


def rows(path: Path):
    return [line for line in path.read_text().splitlines() if not line.startswith("#")]


def report_sizes(record: dict) -> None:
    logs = record["sensor_logs"]
    distance, sim = record["distance_m"], record["sim_duration_s"]
    print(f"sim {sim:.0f} s, {distance:.1f} m driven, {logs['steps']} steps, "
          f"{logs['scans']} scans, stop {record['stop_reason']}")
    wall, rec = record["wall_time_s"], record["timing"]["sensor_logs"]
    cpu, rec_cpu = record["episode_cpu_s"], record["timing"]["sensor_logs_cpu"]
    print(f"episode wall {wall:.1f} s, CPU {cpu:.1f} s; sensor-log recorder wall {rec:.2f} s "
          f"({100 * rec / wall:.1f} %), CPU {rec_cpu:.2f} s ({100 * rec_cpu / cpu:.1f} %) = "
          f"{1e3 * rec_cpu / logs['steps']:.2f} ms CPU per step")
    for name, size in logs["files"].items():
        print(f"{name}: {size / 2**20:.2f} MiB, {size / logs['scans'] / 1024:.2f} KiB/scan, "
              f"{size / 2**20 * 100 / max(distance, 1e-9):.2f} MiB per 100 m, "
              f"{size / 2**20 * 3600 / sim:.1f} MiB per hour of sim time")


def replay(folder: Path) -> None:
    for name in (SENSOR_BAG, SENSOR_LOG):
        out = folder.parent / f"replay_{name}"
        tick = time.perf_counter()
        code = cli(["slam", "run", str(folder / name), "--out", str(out)])
        wall = time.perf_counter() - tick
        same = code == 0 and rows(out / "slam.tum") == rows(folder / SLAM_SCANS)
        stats = json.loads((out / "stats.json").read_text()) if code == 0 else {}
        print(f"replay {name}: {wall:.1f} s wall (GMapping CPU {stats.get('cpu_s', 0):.1f} s), "
              f"trajectory identical to the in-loop one: {same}")


def run(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("world", nargs="?", default=str(ROOT / "worlds" / "office_150.world"))
    parser.add_argument("--max-sim-time", type=float, default=300.0)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--particles", type=int)
    parser.add_argument("--compare", action="store_true")
    args = parser.parse_args(argv)
    warm_all()
    world = Path(args.world)
    with tempfile.TemporaryDirectory(prefix="bench_sensor_logs_") as tmp:
        folder = Path(tmp) / "logged"
        record = episode(world, folder, args, True)
        report_sizes(record)
        if args.compare:
            plain = episode(world, Path(tmp) / "plain", args, False)
            print(f"same episode without sensor logs: wall {plain['wall_time_s']:.1f} s, CPU "
                  f"{plain['episode_cpu_s']:.1f} s (with: {record['wall_time_s']:.1f} s, "
                  f"{record['episode_cpu_s']:.1f} s)")
        replay(folder)
    return 0


if __name__ == "__main__":
    sys.exit(run())
