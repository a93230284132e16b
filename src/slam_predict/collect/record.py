"""Run records: everything one exploration run leaves behind, in ``DATA/<world>/<run-id>/``.

Files (all written inside the episode's temporary folder, which is renamed when complete):
``run.json`` (metadata + metric), ``ground_truth.tum``, ``slam.tum``, ``odom.tum`` (10 Hz,
timestamp x y z qx qy qz qw), ``ground_truth.log`` / ``slam.log`` (CARMEN ``FLASER 0`` lines, as
the thesis fed Freiburg's metricEvaluator), ``map.pgm`` + ``map.yaml`` (final SLAM map,
map_saver values), ``map.png`` (preview), ``snapshots/snapshot_NN.png`` and optionally
``run.bag`` (PoseStamped topics ``/base_pose_ground_truth`` and ``/slam_pose``).

:func:`build_record` is run.json's one builder: the in-process episode
(:mod:`slam_predict.collect.episode`) and the ROS path (:mod:`slam_predict.ros.run_record`)
both call it, so the two records have the same keys computed the same way.
"""
from __future__ import annotations

import functools
import json
import subprocess
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from slam_predict import __version__
from slam_predict.config import to_dict
from slam_predict.formats import carmen, mapserver, tum
from slam_predict.metric.association import dedupe_consecutive
from slam_predict.paths import portable_path

SCHEMA_VERSION = 1
# run.json fields that legitimately differ between two runs with the same seed.
TIMING_FIELDS = ("wall_time_s", "timing")
GT_TOPIC, SLAM_TOPIC = "/base_pose_ground_truth", "/slam_pose"


@dataclass
class Trajectories:
    """Synchronous trajectories of one run: times (N,) s and poses (N, 3) (m, m, rad)."""

    t: np.ndarray
    ground_truth: np.ndarray
    slam: np.ndarray
    odom: np.ndarray

    def adjusted(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(t, slam, ground truth) with consecutive repeated ground-truth poses (pauses) removed,
        the thesis' adjustment before the metric."""
        keep_t, _ = dedupe_consecutive(self.t, self.ground_truth)
        mask = np.isin(self.t, keep_t)
        return self.t[mask], self.slam[mask], self.ground_truth[mask]


@dataclass
class RunInfo:
    """What the batch knows about a run: world name and file (may be empty), index, seed, the
    odometry error model's name and its drawn parameters (None when unknown)."""

    world: str
    world_file: str = ""
    run_index: int = 0
    seed: int = 0
    odometry_model: str = ""
    odometry_error: dict[str, Any] | None = None
    sensor: dict[str, Any] | None = None
    ros: dict[str, Any] = field(default_factory=dict)


@dataclass
class RunEnd:
    """How a run ended: stop reason, the explorer's end ({t, reason} or None), sim and wall
    duration (s), stall count, coverage (0-1, None without a world), the stuck record
    (:meth:`~slam_predict.collect.stopping.StuckDetector.record`, None when not watched) and
    the floor the laser swept (0-1, :func:`slam_predict.explore.seen.swept_coverage`)."""

    stop_reason: str | None
    explorer_end: dict[str, Any] | None
    sim_duration_s: float
    wall_time_s: float
    stalls: int
    coverage: float | None
    stuck: dict[str, Any] | None = None
    coverage_swept: float | None = None


@functools.lru_cache(maxsize=1)
def code_version() -> str:
    """Package version plus the git commit of the source tree, when known."""
    try:
        sha = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                             text=True, cwd=Path(__file__).parent, timeout=5).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        sha = ""
    return f"{__version__}+{sha}" if sha else __version__


NO_METRIC_NOTE = ("one distinct ground-truth pose: the robot never moved, so there is no "
                  "relation to measure")


def with_metric(records: Sequence[dict]) -> list[dict]:
    """The run records that carry an error measurement (``metric`` is null in the record of a
    run whose robot never moved, :func:`measure`)."""
    return [r for r in records if isinstance(r.get("metric"), dict)]


def measure(traj: Trajectories, settings, seed: int) -> dict | None:
    """The run's Kümmerle statistics on the pause-free trajectories (thesis sampling); None
    when they hold fewer than two poses (the robot never moved: :data:`NO_METRIC_NOTE`)."""
    from slam_predict.metric.kummerle import evaluate_sampled

    _, slam, gt = traj.adjusted()
    if len(gt) < 2:
        return None
    m = settings.metric
    result = evaluate_sampled(slam, gt, np.random.default_rng([seed, 1]), pilot=m.pilot,
                              margin_trans=m.margin_trans, margin_rot=m.margin_rot,
                              confidence=m.confidence)
    info = {**result.info, "seed": [int(seed), 1]}   # `metric evaluate --seed S 1` reproduces it
    return {**result.summary(), "info": info, "poses": int(len(gt))}


def build_record(info: RunInfo, settings, hashes: dict[str, str], end: RunEnd,
                 traj: Trajectories, rule, free_area_m2: float | None,
                 timing: dict[str, float], compute_stats: dict | None = None) -> dict[str, Any]:
    """run.json content (without ``schema``) of a finished run.

    Args:
        settings: the :class:`~slam_predict.collect.settings.CollectSettings` of the run.
        hashes: config hashes recorded as ``config_hashes``.
        rule: the run's :class:`~slam_predict.collect.stopping.SnapshotMSE` (its snapshots).
        timing: wall times (s) of the run's parts.
        compute_stats: the compute delay's counters (scans dropped, rebuilds, busy time) when
            it was on; recorded with its settings as ``slam_compute``.
    """
    metric = measure(traj, settings, info.seed)
    return {
        "world": info.world, "world_file": portable_path(info.world_file),
        "run_index": info.run_index, "seed": info.seed, "code_version": code_version(),
        "config_hashes": hashes, "slam": settings.slam.record(),
        "settings_file": portable_path(settings.source),
        "odometry_model": info.odometry_model or settings.sim.odom.model,
        "ranger_model": settings.sim.ranger_model,
        "odometry_error": info.odometry_error, "sensor": info.sensor,
        "stop_reason": end.stop_reason, "explorer_end": end.explorer_end,
        "sim_duration_s": float(end.sim_duration_s), "wall_time_s": float(end.wall_time_s),
        "distance_m": path_length(traj.ground_truth),
        "rotation_rad": path_rotation(traj.ground_truth),
        "coverage": end.coverage, "stalls": int(end.stalls), "free_area_m2": free_area_m2,
        **({"coverage_swept": end.coverage_swept} if end.coverage_swept is not None else {}),
        **({"stuck": end.stuck} if end.stuck is not None else {}),
        "snapshots": [{"t": t, "mse": m}
                      for t, m in zip(rule.times, [None] + rule.mses, strict=False)],
        "metric": metric,
        **({"metric_note": NO_METRIC_NOTE} if metric is None else {}),
        "timing": {k: float(v) for k, v in timing.items()},
        **({"slam_compute": {**to_dict(settings.compute), **compute_stats}}
           if compute_stats is not None else {}),
    }


def path_length(poses: np.ndarray) -> float:
    """Length of a planar path (m)."""
    return float(np.hypot(*np.diff(poses[:, :2], axis=0).T).sum()) if len(poses) > 1 else 0.0


def path_rotation(poses: np.ndarray) -> float:
    """Summed absolute heading change of a path (rad)."""
    if len(poses) < 2:
        return 0.0
    step = np.diff(poses[:, 2])
    return float(np.abs((step + np.pi) % (2 * np.pi) - np.pi).sum())


def write_trajectories(folder: Path, traj: Trajectories) -> None:
    """TUM and CARMEN files of the three trajectories."""
    tum.write_tum(folder / "ground_truth.tum", traj.t, traj.ground_truth)
    tum.write_tum(folder / "slam.tum", traj.t, traj.slam)
    tum.write_tum(folder / "odom.tum", traj.t, traj.odom)
    carmen.write_trajectory(folder / "ground_truth.log", traj.t, traj.ground_truth,
                            odom_poses=traj.odom)
    carmen.write_trajectory(folder / "slam.log", traj.t, traj.slam, odom_poses=traj.odom)


def write_map(folder: Path, grid: np.ndarray, resolution: float,
              origin: tuple[float, float]) -> None:
    """Final SLAM map (OccupancyGrid values, row 0 = bottom) as map_server PGM+YAML and PNG."""
    image = mapserver.occupancy_to_image(grid)
    mapserver.write_map(folder / "map.yaml", image, resolution, (origin[0], origin[1], 0.0))
    cv2.imwrite(str(folder / "map.png"), _crop_known(image))


def write_snapshot(folder: Path, index: int, image: np.ndarray) -> None:
    """One stop-rule snapshot (full-size map_saver image) as PNG."""
    (folder / "snapshots").mkdir(exist_ok=True)
    cv2.imwrite(str(folder / "snapshots" / f"snapshot_{index:02d}.png"), image)


def write_bag(folder: Path, traj: Trajectories) -> None:
    """A ROS bag with ground truth and SLAM poses as PoseStamped topics."""
    from slam_predict.formats.rosbag import write_pose_bag
    write_pose_bag(folder / "run.bag", {GT_TOPIC: (traj.t, traj.ground_truth),
                                        SLAM_TOPIC: (traj.t, traj.slam)})


def write_run_json(folder: Path, record: dict) -> None:
    """run.json (written last: its presence marks a complete record)."""
    (folder / "run.json").write_text(json.dumps({"schema": SCHEMA_VERSION, **record}, indent=1,
                                                sort_keys=True, default=_plain))


def load_record(folder: Path) -> tuple[dict, Trajectories]:
    """Reload a run record: run.json and the three TUM trajectories."""
    folder = Path(folder)
    record = json.loads((folder / "run.json").read_text())
    t, gt = tum.read_tum(folder / "ground_truth.tum")
    _, slam = tum.read_tum(folder / "slam.tum")
    _, odom = tum.read_tum(folder / "odom.tum")
    return record, Trajectories(t, gt, slam, odom)


def ranger_model_of(record: dict) -> str:
    """The simulator's ranger model a run.json records (``exact`` for records written before
    run.json recorded it)."""
    return str(record.get("ranger_model") or "exact")


def without_timing(record: dict) -> dict:
    """A run.json dict minus the fields that depend on the machine's speed."""
    return {k: v for k, v in record.items() if k not in TIMING_FIELDS}


def _crop_known(image: np.ndarray, margin: int = 10) -> np.ndarray:
    known = image != mapserver.UNKNOWN
    if not known.any():
        return image[:1, :1]
    rows, cols = np.flatnonzero(known.any(1)), np.flatnonzero(known.any(0))
    return image[max(rows[0] - margin, 0):rows[-1] + margin + 1,
                 max(cols[0] - margin, 0):cols[-1] + margin + 1]


def _plain(value):
    """JSON default for numpy scalars and arrays."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    raise TypeError(f"not JSON serialisable: {type(value)}")


FILES: list[str] = ["run.json", "ground_truth.tum", "slam.tum", "odom.tum", "ground_truth.log",
                    "slam.log", "map.pgm", "map.yaml", "map.png"]
