"""Offline SLAM runs (any registered back-end) over a recorded log, as a ROS SLAM node would
process the same data.

Input (:func:`read_input`): a ROS bag (:mod:`.bag_input`) or a CARMEN log (:mod:`.scans`).

Outputs of :func:`write_run` (one folder, written atomically): ``slam.tum`` (map-frame robot pose
per processed scan, timestamps copied from the input), ``slam.log`` (the same as a CARMEN
trajectory, raw odometry in the odom fields), ``map.yaml`` + ``map.pgm`` (map_saver format),
``map.png`` (the known part of the map, for viewing), ``stats.json``.
"""
from __future__ import annotations

import json
import logging
import os
import resource
import time
from collections.abc import Callable
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

import numpy as np

from slam_predict import slam as backends
from slam_predict.atomic import atomic_dir
from slam_predict.config import from_dict, to_dict
from slam_predict.errors import InputError
from slam_predict.geometry import compose
from slam_predict.seeds import run_seeds
from slam_predict.slam import OccupancyGrid, SlamBackend
from slam_predict.slam.bag_input import bag_like, read_bag_input
from slam_predict.slam.compute_delay import ComputeDelayConfig, for_backend
from slam_predict.slam.scans import SlamInput, read_carmen_input

LOG = logging.getLogger(__name__)


@dataclass
class RunResult:
    """A finished run: processed-scan indices into the input, times, map-frame robot poses,
    the raw odometry and reference poses at those scans, the final map and statistics;
    ``handed``: with a compute delay, the indices of the scans the back-end was handed (the
    others were dropped while it was busy), else None; ``online``: (N, 3) the robot pose the
    node published at every input scan once it had been offered (map → odom as it stood, composed
    with the scan's odometry), as a closed loop records its SLAM pose each step."""

    indices: np.ndarray
    times: np.ndarray
    poses: np.ndarray
    odometry: np.ndarray
    reference: np.ndarray | None
    grid: OccupancyGrid
    stats: dict
    slam: SlamBackend = field(repr=False, default=None)
    handed: np.ndarray | None = None
    online: np.ndarray | None = None


def read_input(path: os.PathLike | str, max_scans: int | None = None,
               **bag_options) -> SlamInput:
    """Read a CARMEN log or a ROS bag for :func:`run` (first ``max_scans`` scans only, when
    given). ``bag_options`` go to :func:`~.bag_input.read_bag_input` (scan_topic, odom_topic,
    base_frame, odom_frame)."""
    path = os.fspath(path)
    if bag_like(path):
        return read_bag_input(path, max_scans=max_scans, **bag_options)
    if os.path.isdir(path):
        raise InputError("SLAM input is a folder but not a ROS 2 bag", path)
    return read_carmen_input(path, max_scans)


@dataclass
class RecordedRun:
    """The SLAM set-up of a collected run whose sensor log is replayed: its back-end, parameters
    and seed (the SLAM generator is the closed loop's, see :func:`recorded_run`)."""

    slam_type: str
    params: Any
    seed: int
    run_json: str
    compute: Any = None

    def rng(self) -> np.random.Generator:
        """The generator the in-loop SLAM back-end of the run had."""
        return in_loop_slam_rng(self.seed)


def in_loop_slam_rng(seed: int) -> np.random.Generator:
    """The SLAM generator of a collected run with seed ``seed`` (the closed loop's third)."""
    return np.random.default_rng(run_seeds(seed)[2])


def recorded_run(path: os.PathLike | str) -> RecordedRun | None:
    """The :class:`RecordedRun` of a sensor log inside a collected run folder (``run.json``
    beside it with a ``sensor_logs`` entry holding the back-end's parameters), else None."""
    run_json = Path(path).resolve().parent / "run.json"
    if not run_json.is_file():
        return None
    try:
        record = json.loads(run_json.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise InputError(f"cannot read run record: {exc}", run_json) from None
    slam_type = str((record.get("slam") or {}).get("type", "gmapping"))
    sensors = record.get("sensor_logs")
    if not isinstance(sensors, dict) or slam_type not in sensors:
        return None
    params = backends.backend_class(slam_type).params_from_record(
        sensors[slam_type], f"{run_json} sensor_logs.{slam_type}")
    return RecordedRun(slam_type, params, int(record["seed"]), str(run_json),
                       _recorded_compute(record.get("slam_compute"), run_json))


def _recorded_compute(section, run_json: Path):
    """The compute delay a run was collected with (run.json ``slam_compute``), or None."""
    if section is None:
        return None
    keys = {f.name for f in fields(ComputeDelayConfig)}
    settings = {k: v for k, v in section.items() if k in keys}   # without its counters
    return from_dict(ComputeDelayConfig, settings, f"{run_json} slam_compute")


def run(data: SlamInput, slam_type: str, params, seed: int,
        progress: Callable[[int, int], None] | None = None,
        rng: np.random.Generator | None = None, compute=None) -> RunResult:
    """Run back-end ``slam_type`` over ``data`` with a generator seeded by ``seed`` (or ``rng``
    when given, e.g. a collected run's SLAM generator); the map is built at the end.
    ``compute``: a :class:`~slam_predict.slam.compute_delay.ComputeDelayConfig` (a collected
    run's), so the back-end gets the scans the run's GMapping had time for."""
    cpu0, wall0 = time.process_time(), time.perf_counter()
    slam = backends.create(slam_type, params=params, laser=data.laser,
                           rng=rng if rng is not None else np.random.default_rng(seed))
    delay = for_backend(compute, slam, slam.map_update_interval)
    indices, handed = [], []
    map_T_odom = np.zeros(3)
    online = np.empty((len(data), 3))

    def handle(_stamp: float, k: int) -> tuple[bool, np.ndarray]:
        nonlocal map_T_odom
        handed.append(k)
        processed = slam.update(data.odometry[k], data.ranges[k], data.times[k]) is not None
        if processed:
            indices.append(k)
            map_T_odom = np.asarray(slam.map_to_odom(), dtype=float)
        return processed, data.ranges[k]

    for k in range(len(data)):
        if delay is None:
            handle(data.times[k], k)
        else:
            delay.offer(float(data.times[k]), k, handle)
        online[k] = compose(map_T_odom, data.odometry[k])
        if progress is not None:
            progress(k + 1, len(data))
    cpu_filter = time.process_time() - cpu0
    numbers, times, poses = slam.trajectory()
    index = np.asarray(indices, dtype=np.int64)[numbers]
    grid = slam.map()
    stats = {"scans_processed": len(indices), **slam.stats()}
    if delay is not None:
        stats["slam_compute"] = dict(delay.stats)
    stats.update({
        "seed": int(seed),
        "cpu_s": round(time.process_time() - cpu0, 3),
        "cpu_filter_s": round(cpu_filter, 3),
        "wall_s": round(time.perf_counter() - wall0, 3),
        "peak_rss_mib": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0, 1),
    })
    LOG.info("%s: %d/%d scans processed, CPU %.1f s", data.path, stats["scans_processed"],
             len(data), stats["cpu_s"])
    reference = data.reference[index] if data.reference is not None else None
    return RunResult(index, times, poses, data.odometry[index], reference, grid, stats, slam,
                     np.asarray(handed, dtype=np.int64) if delay is not None else None, online)


def evaluate(result: RunResult, n_pairs: int = 5000, seed: int = 0) -> dict:
    """The baseline's error of the run and of the raw odometry against the reference poses."""
    if result.reference is None or len(result.poses) < 2:
        return {}
    from slam_predict.metric import evaluate_against_reference

    out = {}
    for name, est in (("slam", result.poses), ("odometry", result.odometry)):
        summary = evaluate_against_reference(est, result.reference, n_pairs, seed).summary()
        out[name] = {"trans_mean_m": float(summary["trans_mean"]),
                     "rot_mean_deg": float(summary["rot_mean_deg"])}
    return out


def known_window(grid: OccupancyGrid, margin: int = 20):
    """(row slice, column slice) of the grid's known cells plus ``margin`` cells."""
    rows, cols = np.nonzero(grid.data >= 0)
    if rows.size == 0:
        return slice(0, 0), slice(0, 0)
    return (slice(max(rows.min() - margin, 0), rows.max() + margin + 1),
            slice(max(cols.min() - margin, 0), cols.max() + margin + 1))


def write_run(out_dir: os.PathLike | str, result: RunResult, data: SlamInput,
              params, seed: int, config_path: str | None = None) -> Path:
    """Write the run's files into ``out_dir`` (replaced atomically); returns its path."""
    import cv2

    from slam_predict.formats.carmen import write_trajectory
    from slam_predict.formats.mapserver import occupancy_to_image, write_map
    from slam_predict.formats.tum import write_tum

    out_dir = Path(out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError("output path exists and is not a folder", out_dir)
    header = [f"{result.slam.label} (slam_predict) on {data.path}, seed {seed}"]
    image = occupancy_to_image(result.grid.data)
    rows, cols = known_window(result.grid)
    flipped = result.grid.data.shape[0]
    preview = image[flipped - rows.stop:flipped - rows.start, cols]
    with atomic_dir(out_dir) as tmp:
        write_tum(tmp / "slam.tum", result.times, result.poses, header=header)
        write_trajectory(tmp / "slam.log", result.times, result.poses,
                         odom_poses=result.odometry, header=header)
        write_map(tmp / "map.yaml", image, result.grid.resolution, (*result.grid.origin, 0.0))
        if preview.size:
            ok, png = cv2.imencode(".png", preview)
            if ok:
                (tmp / "map.png").write_bytes(png.tobytes())
        stats = dict(result.stats)
        stats.update({"input": data.path, "input_info": data.info, "config": config_path,
                      "slam_type": result.slam.name, "params": to_dict(params),
                      "evaluation": evaluate(result)})
        (tmp / "stats.json").write_text(json.dumps(stats, indent=1) + "\n", encoding="utf-8")
    return out_dir
