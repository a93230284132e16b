"""Differential check: our GMapping port against the real openslam_gmapping, same input,
side by side.

For every log and seed, the log is read once with our runner's reader
(``slam_predict.slam.runner.read_input``); that very input object (odometry, ranges,
beam angles, laser offset, maxRange derivation) is run through our port
(``runner.run``, in-process; by default on the real library's own random stream, drand48 seeded
with the real side's seed, so seed k of both sides is the same run, see ``--ours-stream``) and
exported as "prepared scans"
(``slam_predict.formats.prepared_scans``) for the real library, driven by
``bench/gmapping_diff/driver.cpp`` as the slam_gmapping node drives it (same centred laser, same
robot-pose convention). Both trajectories are evaluated by the same code on their processed
scans against the log's reference poses: ``metric.evaluate_against_reference``, 5,000 random
forward pairs, pair seed 0.

Prints per log: seeds, scans processed (ours / real; flagged when the processed scans differ),
error mean / median / min–max of each side, the ratio of means (ours ÷ real) with a 95 %
bootstrap interval (seeds resampled independently on each side), resamples, mean Neff after scan
matching, and CPU s (ours in-process, real = the driver's CPU time). Acceptance (issue #16):
ratio within [0.85, 1.15] per log.

Usage: bench/bench_gmapping_diff.py --upstream DIR [--logs intel aces|PATH.log.gz ...]
           [--runs RUN_OR_CAMPAIGN_DIR ...] [--seeds 1-10] [--jobs 1] [--set KEY=VALUE ...]
           [--config YAML] [--ours-stream drand48|numpy] [--map-check] [--out DIR]
``--upstream`` (or env SLAM_PREDICT_GMAPPING_UPSTREAM) is an export of
github.com/ros-perception/openslam_gmapping; it is built once into ``<out>/build`` with
``bench/gmapping_diff/build.sh``. Named logs (intel, aces, csail, freiburg-101) use
``../shared/baselines/gmapping_real_<log>.yaml``; any other CARMEN log uses ``--config``
(default: slam_gmapping's defaults). ``--runs`` takes collected run folders (or campaign folders
holding them) with a sensor log: each run's ``sensors.log.gz`` is replayed with the GMapping
parameters its run.json records, and a second table puts both sides' errors beside the run's
own (``gmapping_diff/collected_runs.py``) with the median ratio over runs; a run collected with
the compute delay gives both sides only the scans its in-loop GMapping was handed. ``--set``
overrides parameters on both sides; the real side's beam angles follow ``range_sensor_angles``
(true: the node's RangeSensor angles, false: the scan's own). ``--ours-stream numpy`` runs ours on
``numpy.random.default_rng(seed)`` instead (independent noise: compare distributions, not
seeds). ``--map-check`` adds issue #4's map check per run and side
(``gmapping.runner.map_agreement_with_reference``: % of each map's occupied cells within 2 cells
of the other's after a rigid fit onto the reference; 80 % is the bar). Finished runs are cached
in ``<out>/<variant>/<log>/`` (``ours_<stream>_<seed>.json``, ``real_<seed>.json``) and reused.
"""
from __future__ import annotations

import argparse
import dataclasses
import functools
import json
import os
import resource
import subprocess
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("SLAM_PREDICT_SHARED", ROOT.parent / "shared"))
LOGS = ("intel", "aces", "csail", "freiburg-101")
sys.path.insert(0, str(ROOT / "bench" / "gmapping_diff"))
import collected_runs as collected  # noqa: E402  (bench/gmapping_diff/collected_runs.py)

HANDED_DIR = None  # set by main: <out>/handed, the cached handed-scan lists of collected runs
BUILD_SCRIPT = ROOT / "bench" / "gmapping_diff" / "build.sh"
DRIVER_SOURCE = ROOT / "bench" / "gmapping_diff" / "driver.cpp"
HOW_TO_GET = ("the real openslam_gmapping is needed: put a checkout of "
              "ros-perception/openslam_gmapping OUTSIDE this repository (any folder, e.g. "
              "UPSTREAM_DIR)\nthen pass --upstream UPSTREAM_DIR "
              "(or set SLAM_PREDICT_GMAPPING_UPSTREAM)")


def seeds_arg(text: str):
    if "-" in text:
        lo, hi = text.split("-")
        return list(range(int(lo), int(hi) + 1))
    return [int(v) for v in text.split(",")]


def build_driver(upstream: Path, build: Path) -> Path:
    """Build (or reuse) the driver; rebuilt when driver.cpp is newer than the binary."""
    binary = build / "gmapping_diff_driver"
    if not binary.exists() or DRIVER_SOURCE.stat().st_mtime > binary.stat().st_mtime:
        subprocess.run(["bash", str(BUILD_SCRIPT), str(upstream), str(build)], check=True,
                       stdout=subprocess.DEVNULL)
    return binary


def log_source(name: str, config: str | None):
    """(log path, config path or None, short name) for a named shared log or a CARMEN path."""
    if collected.is_run(Path(name)):
        return Path(name) / collected.SENSOR_LOG, None, collected.run_name(Path(name))
    if name in LOGS:
        return (SHARED / "data" / "slam_inputs" / f"{name}.log.gz",
                SHARED / "baselines" / f"gmapping_real_{name}.yaml", name)
    path = Path(name)
    short = path.name.split(".")[0]
    return path, (Path(config) if config else None), short


def load(log: str, config: str | None, overrides: dict):
    """(SlamInput, GMappingParams, short name); a collected run uses its recorded parameters."""
    return _load(log, config, json.dumps(overrides, sort_keys=True))


@functools.lru_cache(maxsize=2)
def _load(log: str, config: str | None, overrides_json: str):
    from slam_predict.config import load_yaml
    from slam_predict.slam.gmapping.params import params_from_dict, params_from_record
    from slam_predict.slam.runner import read_input

    path, cfg, short = log_source(log, config)
    data = read_input(path)
    if collected.is_run(Path(log)):
        values, origin = collected.recorded_params(Path(log)), f"{log}/run.json"
        cache = Path(HANDED_DIR, f"{short}.txt") if HANDED_DIR else None
        handed = collected.handed_scans(Path(log), data, cache)
        if handed is not None:
            data = data.take(handed)
    else:
        values, origin = (dict(load_yaml(cfg) or {}) if cfg else {}), str(cfg or "--set")
    values.update(json.loads(overrides_json))
    build = params_from_record if collected.is_run(Path(log)) else params_from_dict
    return data, build(values, origin), short


def error_of(data, indices, poses) -> dict:
    from slam_predict.metric import evaluate_against_reference

    summary = evaluate_against_reference(poses, data.reference[indices], 5000, 0).summary()
    return {"trans_mean_m": float(summary["trans_mean"]),
            "rot_mean_deg": float(summary["rot_mean_deg"])}


def run_ours(data, params, seed: int, stream: str = "drand48") -> dict:
    """Our port through the offline runner on random stream ``stream``: ``drand48`` seeded with
    ``seed`` as the real side is, or ``numpy`` (``default_rng(seed)``)."""
    from slam_predict.slam import runner

    params = dataclasses.replace(params, random_stream=stream,
                                 drand48_seed=seed if stream == "drand48" else None)
    cpu0 = time.process_time()
    result = runner.run(data, "gmapping", params, seed)
    return {"indices": result.indices.tolist(), "poses": result.poses.tolist(),
            "neff": result.stats["neff_history"], "resamples": result.stats["resamples"],
            "cpu_s": time.process_time() - cpu0}


def run_port(data, params, rng) -> dict:
    """Our port over ``data`` drawing from ``rng`` (any object with the numpy Generator methods
    the filter calls): processed scans, poses, Neff history, resamples, CPU s."""
    from slam_predict.slam.gmapping.filter import GMapping

    cpu0 = time.process_time()
    slam = GMapping(dataclasses.replace(params, random_stream="numpy"), data.laser, rng)
    indices = [k for k in range(len(data))
               if slam.update(data.odometry[k], data.ranges[k], data.times[k]) is not None]
    numbers, _, poses = slam.trajectory()
    return {"indices": np.asarray(indices)[numbers].tolist(), "poses": poses.tolist(),
            "neff": list(slam.filter.neff_history), "resamples": slam.filter.resamples,
            "cpu_s": time.process_time() - cpu0}


def run_real(data, params, seed: int, driver: Path, folder: Path) -> dict:
    from slam_predict.formats.prepared_scans import read_driver_output, write_prepared_scans
    from slam_predict.slam.gmapping.params import with_ranges

    scans = folder / f"prepared_{seed}.txt"
    traj = folder / f"real_{seed}.traj"
    angle_mode = "node" if params.range_sensor_angles else "exact"
    write_prepared_scans(scans, data.times, data.odometry, data.ranges, data.laser,
                         with_ranges(params, data.laser.range_max), seed, angle_mode)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([str(driver), str(scans), str(traj)], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = read_driver_output(traj)
    scans.unlink()
    return {"indices": out.indices.tolist(), "poses": out.poses.tolist(), "neff": out.neff,
            "resamples": out.resamples,
            "cpu_s": (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)}


def run_job(job) -> dict:
    """One (log, seed, side) run, cached as JSON in <out>/<log>/ (see the module docstring)."""
    log, seed, side, args = job
    data, params, short = load(log, args["config"], args["set"])
    folder = Path(args["out"]) / short
    folder.mkdir(parents=True, exist_ok=True)
    name = f"ours_{args['stream']}" if side == "ours" else side
    cache = folder / f"{name}_{seed}.json"
    if cache.exists():
        return json.loads(cache.read_text())
    if side == "ours":
        record = run_ours(data, params, seed, args["stream"])
    else:
        record = run_real(data, params, seed, Path(args["driver"]), folder)
    record["error"] = error_of(data, np.array(record["indices"]), np.array(record["poses"]))
    record.update({"log": short, "seed": seed, "side": side, "scans": len(data), "source": log})
    cache.write_text(json.dumps(record) + "\n")
    return record


def bootstrap_ratio(ours: np.ndarray, real: np.ndarray, n: int = 10000, seed: int = 0):
    """95 % percentile interval of mean(ours)/mean(real), each side's seeds resampled."""
    rng = np.random.default_rng(seed)
    a = ours[rng.integers(0, len(ours), (n, len(ours)))].mean(axis=1)
    b = real[rng.integers(0, len(real), (n, len(real)))].mean(axis=1)
    return tuple(np.percentile(a / b, [2.5, 97.5]))


def summary_row(log: str, runs: list) -> str:
    ours = [r for r in runs if r["side"] == "ours"]
    real = [r for r in runs if r["side"] == "real"]
    e = {side: np.array([r["error"]["trans_mean_m"] for r in rs])
         for side, rs in (("ours", ours), ("real", real))}
    processed = "/".join(",".join(str(n) for n in sorted({len(r["indices"]) for r in rs}))
                         for rs in (ours, real))
    same = len(ours) == len(real) and all(
        a["indices"] == b["indices"] for a, b in zip(ours, real, strict=True))
    ratio = e["ours"].mean() / e["real"].mean()
    lo, hi = bootstrap_ratio(e["ours"], e["real"])
    cells = [log, str(len(ours)), processed + ("" if same else " (scans differ)")]
    for side in ("ours", "real"):
        v = e[side]
        cells += [f"{v.mean():.3f}", f"{np.median(v):.3f}", f"{v.min():.3f}–{v.max():.3f}"]
    cells += [f"{ratio:.2f}", f"{lo:.2f}–{hi:.2f}",
              f"{np.mean([r['resamples'] for r in ours]):.0f}/"
              f"{np.mean([r['resamples'] for r in real]):.0f}",
              f"{np.mean([np.mean(r['neff']) for r in ours]):.1f}/"
              f"{np.mean([np.mean(r['neff']) for r in real]):.1f}",
              f"{np.mean([r['cpu_s'] for r in ours]):.1f}/"
              f"{np.mean([r['cpu_s'] for r in real]):.1f}"]
    return "| " + " | ".join(cells) + " |"


def table(records: list) -> str:
    head = ("| log | seeds | scans processed ours/real | ours mean (m) | median | min–max "
            "| real mean (m) | median | min–max | ratio | 95 % CI | resamples ours/real "
            "| Neff mean ours/real | CPU s ours/real |")
    lines = [head, "|" + "---|" * 14]
    by_log: dict = {}
    for r in records:
        by_log.setdefault(r["log"], []).append(r)
    lines += [summary_row(log, runs) for log, runs in by_log.items()]
    lines.append("")
    for log, runs in by_log.items():
        for side in ("ours", "real"):
            errs = " ".join(f"{r['error']['trans_mean_m']:.3f}" for r in runs if r["side"] == side)
            lines.append(f"{log} {side}: {errs}")
        lines.append(f"{log} max position difference ours − real per seed (m): "
                     + " ".join(f"{seed}:{diff}" for seed, diff in pose_differences(runs)))
    return "\n".join(lines)


def pose_differences(runs: list) -> list:
    """(seed, largest position difference between the two sides' trajectories, as text) per
    seed run on both sides; "scans differ" when their processed scans do."""
    sides = {(r["seed"], r["side"]): r for r in runs}
    out = []
    for seed in dict.fromkeys(r["seed"] for r in runs):
        ours, real = sides.get((seed, "ours")), sides.get((seed, "real"))
        if ours is None or real is None:
            continue
        if ours["indices"] != real["indices"]:
            out.append((seed, "scans differ"))
            continue
        diff = np.array(ours["poses"])[:, :2] - np.array(real["poses"])[:, :2]
        out.append((seed, f"{np.hypot(diff[:, 0], diff[:, 1]).max():.1e}"))
    return out


def map_check_lines(records: list, config: str | None, overrides: dict) -> list:
    """Per log and side: the map check (ours → reference / reference → ours, %) of each seed."""
    from slam_predict.slam.gmapping.runner import map_agreement_with_reference

    lines = []
    for log in dict.fromkeys(r["log"] for r in records):
        runs = [r for r in records if r["log"] == log]
        source = next(r.get("source", log) for r in runs)
        data, params, _ = load(source, config, overrides)
        for side in ("ours", "real"):
            cells = []
            for r in (r for r in runs if r["side"] == side):
                a, b = map_agreement_with_reference(data, np.array(r["indices"]),
                                                    np.array(r["poses"]), params, 2.0)
                cells.append(f"{r['seed']}:{100 * a:.1f}/{100 * b:.1f}")
            lines.append(f"{log} {side} map check 2 cells (%): " + " ".join(cells))
    return lines


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--upstream", default=os.environ.get("SLAM_PREDICT_GMAPPING_UPSTREAM"))
    parser.add_argument("--logs", nargs="+", help=f"default: {' '.join(LOGS)} (none with --runs)")
    parser.add_argument("--runs", nargs="+", default=[],
                        help="collected run folders (or folders holding them) with sensor logs")
    parser.add_argument("--seeds", type=seeds_arg, default=list(range(1, 4)))
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--set", nargs="*", default=[], metavar="KEY=VALUE",
                        help="GMapping parameter overrides for both sides (YAML values)")
    parser.add_argument("--config", help="slam_gmapping YAML for logs given as paths")
    parser.add_argument("--ours-stream", choices=("drand48", "numpy"), default="drand48",
                        help="our random stream: the real library's (drand48, seeded with the "
                             "real side's seed; default) or numpy's default_rng(seed)")
    parser.add_argument("--map-check", action="store_true",
                        help="also print the 2-cell map check of every run (both sides)")
    parser.add_argument("--out", default=str(ROOT / "out" / "bench_gmapping_diff"))
    args = parser.parse_args()
    if not args.upstream or not Path(args.upstream, "gridfastslam").is_dir():
        print(f"{args.upstream or '--upstream'}: not given or not an openslam_gmapping tree; "
              + HOW_TO_GET, file=sys.stderr)
        return 2
    out = Path(args.out)
    global HANDED_DIR
    HANDED_DIR = str(out / "handed")
    driver = build_driver(Path(args.upstream), out / "build")
    overrides = {k: yaml.safe_load(v) for k, v in (item.split("=", 1) for item in args.set)}
    variant = "_".join(sorted(args.set)) or "default"
    shared = {"config": args.config, "out": str(out / variant), "driver": str(driver),
              "set": overrides, "stream": args.ours_stream}
    run_dirs = [str(p) for p in collected.find_runs(args.runs)] if args.runs else []
    logs = (args.logs or ([] if run_dirs else list(LOGS))) + run_dirs
    jobs = [(log, seed, side, shared) for log in logs for seed in args.seeds
            for side in ("ours", "real")]
    if args.jobs > 1:
        with ProcessPoolExecutor(max_workers=args.jobs) as pool:
            records = list(pool.map(run_job, jobs))
    else:
        records = [run_job(job) for job in jobs]
    commit = (out / "build" / "upstream_commit").read_text().strip()
    print(f"real openslam_gmapping {commit}; overrides: {variant}; "
          f"ours on the {args.ours_stream} stream")
    print(table(records))
    if args.map_check:
        print("\n".join(map_check_lines(records, args.config, overrides)))
    if run_dirs:
        loops = {}
        for run in run_dirs:
            data, _, short = load(run, None, overrides)
            loops[short] = collected.in_loop_errors(Path(run), data)
        print("\ncollected runs (ours = our port, real = openslam_gmapping; ratio of mean ε_t):")
        print(collected.runs_table(records, loops, bootstrap_ratio))
    return 0


if __name__ == "__main__":
    sys.exit(main())
