"""Offline GMapping runs over a CARMEN log, as slam_gmapping would process the same data.

Input: a ROS bag (see :mod:`.bag_input`) or a CARMEN log: ODOM / FLASER / ROBOTLASER1 lines
(plain or .gz). The robot's raw odometry is taken from
each scan's odom fields (FLASER ``odom_*``, ROBOTLASER1 ``robot_*``); the scan's own pose fields
(FLASER ``x y theta``) are kept apart as the reference trajectory. The laser sits
``PARAM robot_frontlaser_offset`` m ahead of the robot centre. When the parameters leave
maxRange unset, the sensor's range_max is the largest reading of the log (CARMEN's no-return
value), so maxRange = that − 0.01 m, as slam_gmapping derives it from ``range_max``.

Outputs of :func:`write_run` (one folder, written atomically): ``slam.tum`` (map-frame robot pose
per processed scan, timestamps copied from the input), ``slam.log`` (the same as a CARMEN
trajectory, raw odometry in the odom fields), ``map.yaml`` + ``map.pgm`` (map_saver format),
``map.png`` (the known part of the map, for viewing), ``stats.json``.
"""
from __future__ import annotations

import json
import logging
import math
import os
import resource
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Optional

import numpy as np

from slam_predict.atomic import atomic_dir
from slam_predict.errors import InputError, require_file
from slam_predict.slam import LaserGeometry, OccupancyGrid
from slam_predict.slam.gmapping.filter import GMapping
from slam_predict.slam.gmapping.params import GMappingParams, params_to_dict

LOG = logging.getLogger(__name__)


@dataclass
class SlamInput:
    """Scans with the robot's odometry: times (N,) s, odometry (N, 3), ranges (N, B) m, the laser,
    and the reference poses (N, 3) when the input has them."""

    path: str
    times: np.ndarray
    odometry: np.ndarray
    ranges: np.ndarray
    laser: LaserGeometry
    reference: Optional[np.ndarray] = None
    info: dict = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.times)


@dataclass
class RunResult:
    """A finished run: processed-scan indices into the input, times, map-frame robot poses,
    the raw odometry and reference poses at those scans, the final map and statistics."""

    indices: np.ndarray
    times: np.ndarray
    poses: np.ndarray
    odometry: np.ndarray
    reference: Optional[np.ndarray]
    grid: OccupancyGrid
    stats: dict
    slam: GMapping = field(repr=False, default=None)


def read_input(path: os.PathLike | str, max_scans: Optional[int] = None,
               **bag_options) -> SlamInput:
    """Read a CARMEN log or a ROS bag for :func:`run` (first ``max_scans`` scans only, when
    given). ``bag_options`` go to :func:`~.bag_input.read_bag_input` (scan_topic, odom_topic,
    base_frame, odom_frame)."""
    from slam_predict.slam.gmapping.bag_input import bag_like, read_bag_input

    path = os.fspath(path)
    if bag_like(path):
        return read_bag_input(path, max_scans=max_scans, **bag_options)
    if os.path.isdir(path):
        raise InputError("SLAM input is a folder but not a ROS 2 bag", path)
    from slam_predict.formats.carmen import read_log

    log = read_log(require_file(path, "SLAM input"))
    scans = log.scans[:max_scans] if max_scans is not None else log.scans
    if not scans:
        raise InputError("no FLASER or ROBOTLASER1 scan in the log", path)
    beams = len(scans[0].ranges)
    if any(len(s.ranges) != beams for s in scans):
        raise InputError("scans have different numbers of beams", path)
    ranges = np.array([s.ranges for s in scans], dtype=np.float64)
    offset = log.param_float("robot_frontlaser_offset", 0.0)
    side_offset = log.param_float("robot_frontlaser_side_offset", 0.0)
    sensor_max = scans[0].max_range
    if not math.isfinite(sensor_max):
        sensor_max = float(np.max(ranges))
    laser = LaserGeometry(scans[0].angles, (offset, side_offset, 0.0), sensor_max)
    return SlamInput(path=path, times=np.array([s.timestamp for s in scans]),
                     odometry=np.array([s.odom_pose for s in scans]), ranges=ranges, laser=laser,
                     reference=np.array([s.pose for s in scans]),
                     info={"format": "carmen", "scan_type": scans[0].kind, "beams": beams,
                           "laser_offset_m": offset, "scans_in_log": len(log.scans)})


@dataclass
class RecordedRun:
    """The GMapping set-up of a collected run whose sensor log is replayed: its parameters and
    its seed (the SLAM generator is the closed loop's, see :func:`recorded_run`)."""

    params: GMappingParams
    seed: int
    run_json: str

    def rng(self) -> np.random.Generator:
        """The generator the in-loop GMapping of the run had."""
        from slam_predict.explore.loop import loop_seeds
        return np.random.default_rng(loop_seeds(self.seed)[2])


def recorded_run(path: os.PathLike | str) -> Optional[RecordedRun]:
    """The :class:`RecordedRun` of a sensor log inside a collected run folder (``run.json``
    beside it with a ``sensor_logs`` entry), else None."""
    from slam_predict.slam.gmapping.params import params_from_dict

    run_json = Path(path).resolve().parent / "run.json"
    if not run_json.is_file():
        return None
    try:
        record = json.loads(run_json.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise InputError(f"cannot read run record: {exc}", run_json)
    sensors = record.get("sensor_logs")
    if not isinstance(sensors, dict) or "gmapping" not in sensors:
        return None
    return RecordedRun(params_from_dict(sensors["gmapping"], f"{run_json} sensor_logs.gmapping"),
                       int(record["seed"]), str(run_json))


def run(data: SlamInput, params: GMappingParams, seed: int,
        progress: Optional[Callable[[int, int], None]] = None,
        rng: Optional[np.random.Generator] = None) -> RunResult:
    """Run GMapping over ``data`` with a generator seeded by ``seed`` (or ``rng`` when given,
    e.g. a collected run's SLAM generator); the map is built at the end."""
    cpu0, wall0 = time.process_time(), time.perf_counter()
    slam = GMapping(params, data.laser, rng if rng is not None else np.random.default_rng(seed))
    indices = []
    for k in range(len(data)):
        if slam.update(data.odometry[k], data.ranges[k], data.times[k]) is not None:
            indices.append(k)
        if progress is not None:
            progress(k + 1, len(data))
    cpu_filter = time.process_time() - cpu0
    numbers, times, poses = slam.trajectory()
    index = np.asarray(indices, dtype=np.int64)[numbers]
    grid = slam.map()
    stats = slam.stats()
    stats.update({
        "seed": int(seed),
        "cpu_s": round(time.process_time() - cpu0, 3),
        "cpu_filter_s": round(cpu_filter, 3),
        "wall_s": round(time.perf_counter() - wall0, 3),
        "peak_rss_mib": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0, 1),
        "neff_history": [round(v, 3) for v in slam.filter.neff_history],
        "maxRange": slam.params.maxRange,
        "maxUrange": slam.params.maxUrange,
    })
    LOG.info("%s: %d/%d scans processed, %d resamples, CPU %.1f s", data.path,
             stats["scans_processed"], len(data), stats["resamples"], stats["cpu_s"])
    reference = data.reference[index] if data.reference is not None else None
    return RunResult(index, times, poses, data.odometry[index], reference, grid, stats, slam)


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
              params: GMappingParams, seed: int, config_path: Optional[str] = None) -> Path:
    """Write the run's files into ``out_dir`` (replaced atomically); returns its path."""
    import cv2

    from slam_predict.formats.carmen import write_trajectory
    from slam_predict.formats.mapserver import occupancy_to_image, write_map
    from slam_predict.formats.tum import write_tum

    out_dir = Path(out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError("output path exists and is not a folder", out_dir)
    header = [f"GMapping (slam_predict) on {data.path}, seed {seed}"]
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
                      "params": params_to_dict(params), "evaluation": evaluate(result)})
        (tmp / "stats.json").write_text(json.dumps(stats, indent=1) + "\n", encoding="utf-8")
    return out_dir


def map_check(result: RunResult, data: SlamInput, tol: float = 2.0):
    """Map agreement of a run with the reference (see :func:`map_agreement_with_reference`)."""
    return map_agreement_with_reference(data, result.indices, result.poses, result.slam.params,
                                        tol)


def map_agreement_with_reference(data: SlamInput, indices: np.ndarray, poses: np.ndarray,
                                 params: GMappingParams, tol: float = 2.0):
    """(share of our occupied cells within ``tol`` cells of an occupied cell of the reference
    map, and the converse).

    ``poses`` are our map-frame robot poses at the input scans ``indices``. They are first fitted
    rigidly onto the reference poses; both maps are then built from the same scans with the
    published-map rules on a common geometry, the reference one from the reference poses.
    """
    from slam_predict.geometry import compose
    from slam_predict.slam.compare import apply_transform, map_agreement, rigid_fit
    from slam_predict.slam.gmapping.filter import centred_laser
    from slam_predict.slam.gmapping.gridmap import MapBuilder
    from slam_predict.slam.gmapping.params import with_ranges

    if data.reference is None:
        raise ValueError("the input has no reference poses")
    reference = data.reference[indices]
    laser_in_base, angles = centred_laser(data.laser)
    fitted = apply_transform(rigid_fit(poses, reference), poses)
    ours = compose(fitted, laser_in_base)
    ref = compose(reference, laser_in_base)
    readings = data.ranges[indices]
    builder = MapBuilder(with_ranges(params, data.laser.range_max), angles)
    geometry = builder.geometry(ref, readings, start=builder.geometry(ours, readings))
    a = builder.render(geometry, ours, readings)
    b = builder.render(geometry, ref, readings)
    return map_agreement(a.data, b.data, tol)
