"""Collected runs as inputs of the differential check (``bench_gmapping_diff.py --runs``).

A collected run folder (``slam-predict collect`` with ``sensor_logs: true``) holds
``sensors.log.gz`` (CARMEN, ground truth as the reference poses), ``run.json`` (its ``sensor_logs``
entry records the in-loop GMapping parameters) and ``slam_scans.tum`` (the in-loop GMapping's
final best-particle trajectory at its processed scans). Both sides of the check replay the log
with the run's recorded parameters. A run collected with slam_gmapping's compute delay
(run.json ``slam_compute``) is replayed on both sides with only the scans its in-loop GMapping was
handed (:func:`handed_scans`), so both GMappings see the in-loop scan sequence. The run's own
errors are reported beside theirs:

- ``loop_trans_m`` / ``loop_rot_deg``: run.json ``metric`` (the campaign's figure: thesis
  sampling on the pause-free online trajectory);
- ``scans_trans_m`` / ``scans_rot_deg``: ``slam_scans.tum`` scored like both sides of the check
  (``metric.evaluate_against_reference`` on the processed scans, 5,000 pairs, pair seed 0).
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

SENSOR_LOG, RUN_JSON, SLAM_SCANS = "sensors.log.gz", "run.json", "slam_scans.tum"


def is_run(folder: Path, backend: str | None = "gmapping") -> bool:
    """True for a run folder with a sensor log and a run.json that records the parameters of
    its in-loop SLAM ``backend`` (None: of whichever back-end the run used)."""
    run_json = folder / RUN_JSON
    if not (folder / SENSOR_LOG).is_file() or not run_json.is_file():
        return False
    logs = json.loads(run_json.read_text()).get("sensor_logs") or {}
    return bool(logs) if backend is None else backend in logs


def find_runs(paths, backend: str | None = "gmapping") -> list:
    """Run folders among ``paths`` (each a run folder, or a folder searched for run folders)."""
    found = []
    for path in map(Path, paths):
        if is_run(path, backend):
            found.append(path)
            continue
        found += sorted(p.parent for p in path.rglob(RUN_JSON) if is_run(p.parent, backend))
    if not found:
        raise SystemExit(f"{' '.join(map(str, paths))}: no run folder with {SENSOR_LOG} and a "
                         f"{RUN_JSON} 'sensor_logs' entry (collect with sensor_logs: true)")
    return found


def run_name(folder: Path) -> str:
    """Short name of a run: ``<world>-<run folder>`` (e.g. ``Borchen4_updated-run_000``)."""
    record = json.loads((folder / RUN_JSON).read_text())
    return f"{record['world']}-{folder.name}"


def recorded_params(folder: Path) -> dict:
    """The in-loop GMapping parameters (ROS names) recorded in run.json."""
    return dict(json.loads((folder / RUN_JSON).read_text())["sensor_logs"]["gmapping"])


def handed_scans(folder: Path, data, cache: Path | None = None) -> np.ndarray | None:
    """Indices of the log's scans the in-loop GMapping was handed under the run's compute delay
    (None when the run had none): our replay with the run's recorded generator and delay, which
    reproduces the in-loop trajectory (checked against ``slam_scans.tum``). Cached in ``cache``."""
    from slam_predict.formats.tum import read_tum
    from slam_predict.slam import runner

    setup = runner.recorded_run(folder / SENSOR_LOG)
    if setup is None or setup.compute is None or setup.compute.model == "none":
        return None
    if cache is not None and cache.is_file():
        return np.loadtxt(cache, dtype=np.int64, ndmin=1)
    replay = runner.run(data, setup.slam_type, setup.params, setup.seed, rng=setup.rng(),
                        compute=setup.compute)
    times, poses = read_tum(folder / SLAM_SCANS)
    if not (np.allclose(replay.times, times, atol=1e-6) and np.allclose(replay.poses[:, :2],
                                                                        poses[:, :2], atol=1e-6)):
        raise SystemExit(f"{folder}: the replay does not reproduce {SLAM_SCANS}")
    if cache is not None:
        cache.parent.mkdir(parents=True, exist_ok=True)
        np.savetxt(cache, replay.handed, fmt="%d")
    return replay.handed


def match_times(log_times: np.ndarray, times: np.ndarray, tolerance_s: float = 1e-6):
    """Index into ``log_times`` (sorted) of each of ``times``; ValueError if one has no match."""
    log_times = np.asarray(log_times, float)
    index = np.clip(np.searchsorted(log_times, times), 1, len(log_times) - 1)
    earlier = np.abs(log_times[index - 1] - times) <= np.abs(log_times[index] - times)
    index = np.where(earlier, index - 1, index)
    worst = float(np.max(np.abs(log_times[index] - times))) if len(times) else 0.0
    if worst > tolerance_s:
        raise ValueError(f"{worst:.3g} s between a trajectory stamp and the nearest scan")
    return index


def in_loop_errors(folder: Path, data) -> dict:
    """The run's own errors (see the module docstring); ``data`` is the log's SlamInput."""
    from slam_predict.formats.tum import read_tum
    from slam_predict.metric import evaluate_against_reference

    metric = json.loads((folder / RUN_JSON).read_text())["metric"]
    times, poses = read_tum(folder / SLAM_SCANS)
    index = match_times(data.times, times)
    summary = evaluate_against_reference(poses, data.reference[index], 5000, 0).summary()
    return {"loop_trans_m": float(metric["trans_mean"]),
            "loop_rot_deg": math.degrees(float(metric["rot_mean"])),
            "scans_trans_m": float(summary["trans_mean"]),
            "scans_rot_deg": float(summary["rot_mean_deg"]), "slam_scans": int(len(times))}


def runs_table(records: list, loops: dict, bootstrap) -> str:
    """Per run: each side's mean errors (m, deg), ratio of mean ε_t with its 95 % interval
    (``bootstrap(ours, real)``), the run's own errors; then the median ratio over runs."""
    lines = ["| run | seeds | ε_t ours (m) | ε_t real (m) | ratio | 95 % CI | ε_r ours / real (°) "
             "| in-loop slam_scans ε_t (m) / ε_r (°) | run.json ε_t (m) / ε_r (°) |",
             "|" + "---|" * 9]
    ratios = []
    for name, loop in loops.items():
        side = {s: [r for r in records if r["log"] == name and r["side"] == s]
                for s in ("ours", "real")}
        trans = {s: np.array([r["error"]["trans_mean_m"] for r in rs]) for s, rs in side.items()}
        rot = {s: np.mean([r["error"]["rot_mean_deg"] for r in rs]) for s, rs in side.items()}
        ratio = trans["ours"].mean() / trans["real"].mean()
        lo, hi = bootstrap(trans["ours"], trans["real"])
        ratios.append(ratio)
        lines.append(
            f"| {name} | {len(trans['ours'])}/{len(trans['real'])} | {trans['ours'].mean():.3f} "
            f"| {trans['real'].mean():.3f} | {ratio:.2f} | {lo:.2f}–{hi:.2f} "
            f"| {rot['ours']:.3f} / {rot['real']:.3f} "
            f"| {loop['scans_trans_m']:.3f} / {loop['scans_rot_deg']:.3f} "
            f"| {loop['loop_trans_m']:.3f} / {loop['loop_rot_deg']:.3f} |")
    lines += ["", f"median ratio over {len(ratios)} runs: {np.median(ratios):.2f} "
                  f"(min {min(ratios):.2f}, max {max(ratios):.2f})"]
    return "\n".join(lines)
