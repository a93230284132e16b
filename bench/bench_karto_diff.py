"""Differential check: our Karto port against the real Karto SDK of slam_toolbox (its
karto_sdk with slam_toolbox's Ceres solver), same input, side by side.

Each log is read once with our runner's reader (``slam_predict.slam.runner.read_input``); that
very input object is run through our back-end ``karto`` (``runner.run``, in-process, when the
registry has it) and exported as Karto prepared scans (``slam_predict.formats.karto_scans``) for
the real library, driven by ``bench/karto_diff/driver.cpp`` as slam_toolbox's ``addScan`` drives
it (odometric = corrected pose = the odometry pose; slam_toolbox's scan gate with its
``minimum_time_interval`` rule in front of ``Mapper::Process``; the Ceres solver attached).
Both sides get the same parameters (and ours the real side's gate as ``scan_gate``, when its
parameters have that entry): slam_toolbox's YAML (default: the upstream
``config/mapper_params_online_async.yaml``) plus ``--set`` overrides. Both trajectories are
scored by the same code on their accepted scans against the log's reference poses:
``metric.evaluate_against_reference``, 5,000 random forward pairs, pair seed 0.

Prints per log: input scans; accepted scans ours / real (identical sets?); loop closures ours /
real (identical?); share of the real side's accepted scans that ours accepted with a position
within 1 cm; ε_t mean of each side (m) and the ratio ours ÷ real; CPU s of each side; the real
side's mean CPU per ``Process`` call and per ``OccupancyGrid::CreateFromScans`` at the last
timed point.

Usage: bench/bench_karto_diff.py --upstream DIR [--logs intel aces|PATH.log.gz ...]
           [--runs RUN_OR_CAMPAIGN_DIR ...] [--config YAML] [--set KEY=VALUE ...]
           [--gate sync|none] [--threads 1] [--out DIR]
With more than one log a last row gives the medians (and how many logs agree exactly).
``--upstream`` (or env SLAM_PREDICT_KARTO_UPSTREAM) is an export of the ``slam_toolbox`` package
folder of github.com/SteveMacenski/slam_toolbox (noetic-devel); it is built once into
``<out>/build`` with ``bench/karto_diff/build.sh``. ``--runs`` adds collected run folders' sensor
logs. Results are cached in ``<out>/<log>/`` (``<out>/<variant>/<log>/`` with ``--set`` or
``--gate none``, the variant naming both):
``scans.txt`` (the driver's input), ``params.json`` (both sides' parameters), ``real.json``
(the driver's output), ``ours.json``; delete them to rerun.
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("SLAM_PREDICT_SHARED", ROOT.parent / "shared"))
LOGS = ("intel", "aces", "csail", "freiburg-101")
BACKEND = "karto"
sys.path.insert(0, str(ROOT / "bench" / "gmapping_diff"))
import collected_runs as collected  # noqa: E402  (bench/gmapping_diff/collected_runs.py)

BUILD_SCRIPT = ROOT / "bench" / "karto_diff" / "build.sh"
DRIVER_SOURCE = ROOT / "bench" / "karto_diff" / "driver.cpp"
UPSTREAM_CONFIG = Path("config") / "mapper_params_online_async.yaml"
HOW_TO_GET = ("the real Karto SDK is needed: export the slam_toolbox package folder of "
              "SteveMacenski/slam_toolbox (branch noetic-devel) OUTSIDE this repository (e.g. "
              "UPSTREAM_DIR, holding lib/karto_sdk and solvers)\nthen pass --upstream "
              "UPSTREAM_DIR (or set SLAM_PREDICT_KARTO_UPSTREAM)")
POSE_TOLERANCE_M = 0.01


def build_driver(upstream: Path, build: Path) -> Path:
    """Build (or reuse) the driver; rebuilt when driver.cpp or build.sh is newer."""
    binary = build / "karto_diff_driver"
    newest = max(DRIVER_SOURCE.stat().st_mtime, BUILD_SCRIPT.stat().st_mtime)
    if not binary.exists() or newest > binary.stat().st_mtime:
        subprocess.run(["bash", str(BUILD_SCRIPT), str(upstream), str(build)], check=True,
                       stdout=subprocess.DEVNULL)
    return binary


def log_source(name: str) -> tuple[Path, str]:
    """(log path, short name) of a shared log name, a collected run folder or a log path."""
    if collected.is_run(Path(name), None):
        return Path(name) / collected.SENSOR_LOG, collected.run_name(Path(name))
    if name in LOGS or name == "freiburg-079":
        return SHARED / "data" / "slam_inputs" / f"{name}.log.gz", name
    return Path(name), Path(name).name.split(".")[0]


def parameters(config: Path, overrides: list[str]) -> dict:
    """slam_toolbox's flat parameters from ``config`` with ``KEY=VALUE`` overrides (YAML)."""
    values = dict(yaml.safe_load(config.read_text()) or {})
    for item in overrides:
        key, value = item.split("=", 1)
        values[key] = yaml.safe_load(value)
    return values


def error_of(data, indices, poses) -> dict:
    from slam_predict.metric import evaluate_against_reference

    if data.reference is None or len(indices) < 2:
        return {"trans_mean_m": float("nan"), "rot_mean_deg": float("nan")}
    summary = evaluate_against_reference(poses, data.reference[indices], 5000, 0).summary()
    return {"trans_mean_m": float(summary["trans_mean"]),
            "rot_mean_deg": float(summary["rot_mean_deg"])}


def ours_available() -> bool:
    from slam_predict import slam as backends

    return BACKEND in backends.available()


def known_to(cls, values: dict) -> dict:
    """The entries of ``values`` the back-end's (dataclass) parameters have; the node-only ones
    (frames, topics, ...) are left out so its strict parser accepts the file."""
    defaults = cls.default_params()
    if not dataclasses.is_dataclass(defaults):
        return dict(values)
    names = {f.name for f in dataclasses.fields(defaults)}
    return {k: v for k, v in values.items() if k in names}


def run_ours(data, values: dict) -> dict:
    """Our back-end over ``data`` (seed 0: Karto draws no random numbers)."""
    from slam_predict import slam as backends
    from slam_predict.slam import runner

    cls = backends.backend_class(BACKEND)
    params = cls.params_from_dict(known_to(cls, values), "bench_karto_diff")
    cpu0 = time.process_time()
    result = runner.run(data, BACKEND, params, 0)
    loops = result.stats.get("loop_closures", [])
    return {"indices": result.indices.tolist(), "poses": result.poses.tolist(),
            "loop_closures": [list(map(int, pair)) for pair in loops],
            "cpu_s": time.process_time() - cpu0}


def run_real(data, folder: Path, driver: Path, gate: str, threads: int) -> dict:
    """The real library over ``data``; the driver's JSON is kept as ``real.json``."""
    from slam_predict.formats.karto_scans import read_karto_driver_output, write_karto_scans

    scans, output = folder / "scans.txt", folder / "real.json"
    write_karto_scans(scans, data.times, data.odometry, data.ranges, data.laser)
    subprocess.run([str(driver), str(scans), str(folder / "params.json"), str(output),
                    "--gate", gate, "--threads", str(threads)], check=True,
                   stdout=subprocess.DEVNULL, env={**os.environ, "GLOG_minloglevel": "2"})
    out = read_karto_driver_output(output)
    grid = out.grid_cpu[-1] if out.grid_cpu else {}
    return {"indices": out.indices.tolist(), "poses": out.poses.tolist(),
            "loop_closures": out.loop_closures.tolist(), "cpu_s": out.cpu_total_s,
            "process_ms": 1000 * float(np.mean(out.process_cpu[:, 1])),
            "grid_ms": 1000 * float(grid.get("cpu_s", float("nan"))),
            "grid_scans": int(grid.get("accepted", 0))}


def side(name: str, data, folder: Path, run) -> dict:
    """One side's record, cached as ``<folder>/<name>_summary.json``."""
    cache = folder / f"{name}_summary.json"
    if cache.exists():
        return json.loads(cache.read_text())
    record = run()
    record["error"] = error_of(data, np.array(record["indices"], dtype=np.int64),
                               np.array(record["poses"]).reshape(-1, 3))
    cache.write_text(json.dumps(record) + "\n")
    return record


def within_tolerance(ours: dict, real: dict) -> float:
    """Share of the real side's accepted scans that ours accepted within 1 cm of its pose."""
    if not real["indices"]:
        return float("nan")
    mine = dict(zip(ours["indices"], (p[:2] for p in ours["poses"]), strict=True))
    close = sum(1 for k, p in zip(real["indices"], real["poses"], strict=True)
                if k in mine and np.hypot(*np.subtract(mine[k], p[:2])) <= POSE_TOLERANCE_M)
    return close / len(real["indices"])


def agreement(ours: dict, real: dict) -> dict:
    """The acceptance figures of one log: same accepted scans, same loop closures, share of
    poses within 1 cm, ε_t ratio ours ÷ real."""
    return {"accepted_same": ours["indices"] == real["indices"],
            "closures_same": ours["loop_closures"] == real["loop_closures"],
            "within_1cm": within_tolerance(ours, real),
            "ratio": ours["error"]["trans_mean_m"] / real["error"]["trans_mean_m"],
            "cpu_ours_s": ours["cpu_s"], "cpu_real_s": real["cpu_s"]}


def median_row(figures: list[dict]) -> str:
    """Median over the logs (runs) of the acceptance figures; counts for the yes/no ones."""
    def med(key):
        return float(np.median([f[key] for f in figures]))

    n = len(figures)
    return (f"| median of {n} | | | {sum(f['accepted_same'] for f in figures)}/{n} same | | "
            f"{sum(f['closures_same'] for f in figures)}/{n} same | "
            f"{100 * med('within_1cm'):.1f} | | | {med('ratio'):.2f} | "
            f"{med('cpu_ours_s'):.1f} / {med('cpu_real_s'):.1f} | | |")


def row(log: str, scans: int, ours: dict | None, real: dict) -> str:
    e_real = real["error"]["trans_mean_m"]
    cells = [log, str(scans)]
    if ours is None:
        cells += [f"– / {len(real['indices'])}", "–", f"– / {len(real['loop_closures'])}", "–",
                  "–", "–", f"{e_real:.3f}", "–", f"– / {real['cpu_s']:.1f}"]
    else:
        e_ours = ours["error"]["trans_mean_m"]
        cells += [f"{len(ours['indices'])} / {len(real['indices'])}",
                  "yes" if ours["indices"] == real["indices"] else "no",
                  f"{len(ours['loop_closures'])} / {len(real['loop_closures'])}",
                  "yes" if ours["loop_closures"] == real["loop_closures"] else "no",
                  f"{100 * within_tolerance(ours, real):.1f}", f"{e_ours:.3f}",
                  f"{e_real:.3f}", f"{e_ours / e_real:.2f}",
                  f"{ours['cpu_s']:.1f} / {real['cpu_s']:.1f}"]
    cells += [f"{real['process_ms']:.1f}", f"{real['grid_ms']:.1f} ({real['grid_scans']})"]
    return "| " + " | ".join(cells) + " |"


HEADER = ("| log | input scans | accepted ours / real | identical | loop closures ours / real "
          "| identical | poses ≤ 1 cm (%) | ε_t ours (m) | ε_t real (m) | ratio | CPU s ours / "
          "real | real ms per Process | real ms per grid build (scans) |")


def compare(log: str, values: dict, args, driver: Path, with_ours: bool):
    """(table row, agreement figures or None) of one log or run."""
    from slam_predict.slam.runner import read_input

    path, short = log_source(log)
    variant = "_".join(sorted(args.set) + ([f"gate_{args.gate}"] if args.gate != "sync" else []))
    folder = Path(args.out) / variant / short if variant else Path(args.out) / short
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "params.json").write_text(json.dumps(values, indent=1, sort_keys=True) + "\n")
    data = read_input(path)
    real = side("real", data, folder,
                lambda: run_real(data, folder, driver, args.gate, args.threads))
    mine = {**values, "scan_gate": args.gate}  # dropped by known_to when ours has no such key
    ours = side("ours", data, folder, lambda: run_ours(data, mine)) if with_ours else None
    return row(short, len(data), ours, real), (agreement(ours, real) if ours else None)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--upstream", default=os.environ.get("SLAM_PREDICT_KARTO_UPSTREAM"))
    parser.add_argument("--logs", nargs="+", help=f"default: {' '.join(LOGS)} (none with --runs)")
    parser.add_argument("--runs", nargs="+", default=[],
                        help="collected run folders (or folders holding them) with sensor logs")
    parser.add_argument("--config", help="slam_toolbox parameter YAML (default: upstream's "
                                         f"{UPSTREAM_CONFIG})")
    parser.add_argument("--set", nargs="*", default=[], metavar="KEY=VALUE",
                        help="parameter overrides for both sides (YAML values)")
    parser.add_argument("--gate", choices=("sync", "none"), default="sync",
                        help="real side: slam_toolbox's scan gate before Process (sync) or none")
    parser.add_argument("--threads", type=int, default=1, help="real side's TBB threads")
    parser.add_argument("--out", default=str(ROOT / "out" / "bench_karto_diff"))
    args = parser.parse_args()
    upstream = Path(args.upstream) if args.upstream else None
    if upstream is None or not (upstream / "lib" / "karto_sdk").is_dir():
        print(f"{args.upstream or '--upstream'}: not given or not a slam_toolbox package tree; "
              + HOW_TO_GET, file=sys.stderr)
        return 2
    driver = build_driver(upstream, Path(args.out) / "build")
    values = parameters(Path(args.config) if args.config else upstream / UPSTREAM_CONFIG,
                        args.set)
    run_dirs = [str(p) for p in collected.find_runs(args.runs, None)] if args.runs else []
    logs = (args.logs or ([] if run_dirs else list(LOGS))) + run_dirs
    with_ours = ours_available()
    commit = (Path(args.out) / "build" / "upstream_commit").read_text().strip()
    print(f"real slam_toolbox karto_sdk + Ceres solver {commit}; gate {args.gate}; "
          f"overrides: {' '.join(args.set) or 'none'}")
    if not with_ours:
        print(f"back-end '{BACKEND}' is not registered: only the real side is run")
    print(HEADER)
    print("|" + "---|" * (HEADER.count("|") - 1))
    figures = []
    for log in logs:
        text, figure = compare(log, values, args, driver, with_ours)
        print(text, flush=True)
        figures += [figure] if figure else []
    if len(figures) > 1:
        print(median_row(figures))
    return 0


if __name__ == "__main__":
    sys.exit(main())
