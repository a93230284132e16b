"""Per-building summary table ``DATA/summary.csv``, regenerated from the run records.

One row per (world, robot): ``robot`` is the robot configuration hash
(:func:`slam_predict.sensor.sensor_hash` of run.json's ``sensor``, + ``+stage`` for runs with
Stage's ranger model; empty for run records written
before run.json recorded the sensor, so older campaigns keep one row per world), so runs of two
robot configurations in one world give two rows. Columns (m, rad): world, runs, trans_mean,
trans_std, rot_mean, rot_std (mean and std over runs of each run's mean absolute relation error),
path_length_mean, rotation_mean (ground-truth path), the squared-error variants trans_sqr_mean,
trans_sqr_std, rot_sqr_mean, rot_sqr_std, coverage_mean, sim_time_mean_s, and robot (last, so
scripts that address the older columns by position keep working). Std over runs uses ddof = 0,
as the seed study's tables (numpy ``std``).
"""
from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np

from slam_predict.atomic import write_text
from slam_predict.collect.record import ranger_model_of, with_metric
from slam_predict.collect.store import RunStore
from slam_predict.metric.runs import BUILDING_STD_DDOF
from slam_predict.sensor import sensor_hash

KEY_COLUMNS = ("world", "robot")
# robot last: scripts address the older columns by position (tools/train_own_model.sh: runs = $2)
COLUMNS = ("world", "runs", "trans_mean", "trans_std", "rot_mean", "rot_std",
           "path_length_mean", "rotation_mean", "trans_sqr_mean", "trans_sqr_std",
           "rot_sqr_mean", "rot_sqr_std", "coverage_mean", "sim_time_mean_s", "robot")


def robot_key(record: dict) -> str:
    """The robot configuration hash of a run.json record ('' when it has no ``sensor``), with
    ``+stage`` appended for runs simulated with Stage's ranger (so exact runs keep their key)."""
    sensor = record.get("sensor")
    key = sensor_hash(sensor) if sensor else ""
    model = ranger_model_of(record)
    return key if model == "exact" else f"{key}+{model}"


def by_robot(records: list[dict]) -> dict[str, list[dict]]:
    """The records grouped by :func:`robot_key`, keys sorted."""
    groups: dict[str, list[dict]] = {}
    for record in records:
        groups.setdefault(robot_key(record), []).append(record)
    return dict(sorted(groups.items()))


def building_row(world: str, records: list[dict], robot: str = "") -> dict[str, float]:
    """One summary row from the run.json records of ``world`` run with robot ``robot``."""
    def values(*keys: str) -> np.ndarray:
        out = []
        for record in records:
            value = record
            for key in keys:
                value = value[key]
            out.append(float(value))
        return np.asarray(out)

    trans, rot = values("metric", "trans_mean"), values("metric", "rot_mean")
    trans_sqr, rot_sqr = values("metric", "trans_sqr_mean"), values("metric", "rot_sqr_mean")
    return {
        "world": world, "robot": robot, "runs": len(records),
        "trans_mean": trans.mean(), "trans_std": trans.std(ddof=BUILDING_STD_DDOF),
        "rot_mean": rot.mean(), "rot_std": rot.std(ddof=BUILDING_STD_DDOF),
        "path_length_mean": values("distance_m").mean(),
        "rotation_mean": values("rotation_rad").mean(),
        "trans_sqr_mean": trans_sqr.mean(), "trans_sqr_std": trans_sqr.std(ddof=BUILDING_STD_DDOF),
        "rot_sqr_mean": rot_sqr.mean(), "rot_sqr_std": rot_sqr.std(ddof=BUILDING_STD_DDOF),
        "coverage_mean": values("coverage").mean(),
        "sim_time_mean_s": values("sim_duration_s").mean(),
    }


def write_summary(data_dir: Path) -> Path:
    """Regenerate ``data_dir/summary.csv`` from every complete run; returns its path."""
    store = RunStore(Path(data_dir))
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=COLUMNS, lineterminator="\n")
    writer.writeheader()
    for world in store.worlds():
        for robot, records in by_robot(with_metric(store.records(world))).items():
            row = building_row(world, records, robot)
            writer.writerow({k: (f"{v:.9g}" if isinstance(v, float) else v)
                             for k, v in row.items()})
    path = Path(data_dir) / "summary.csv"
    write_text(path, buffer.getvalue())
    return path
