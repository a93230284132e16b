"""A small campaign folder built in tmp with the real record writers (no simulation).

World ``alpha``: 3 runs with trajectories and a final map; world ``beta``: 2 runs, the second
kept as run.json only (as committed campaigns are). Errors are fixed numbers so tests can check
the report's tables against them.
"""
from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np

from slam_predict.collect import record as rec
from slam_predict.collect.summary import write_summary
from slam_predict.geometry import compose, inverse

HASHES = {"sim": "s1", "gmapping": "g1", "nav": "n1", "explore": "e1", "stop": "p1",
          "metric": "m1"}
ERRORS = {  # world → per run (trans_mean m, rot_mean rad)
    "alpha": [(0.10, 0.010), (0.20, 0.020), (0.30, 0.030)],
    "beta": [(0.05, 0.004), (0.07, 0.008)],
}
START = {"alpha": (2.0, 1.0, 0.5), "beta": (-1.0, 3.0, -1.0)}
MAP_ORIGIN = (-4.0, -3.0, 0.0)
RESOLUTION = 0.1


def trajectories(world: str, index: int) -> rec.Trajectories:
    """A loop in the world frame; SLAM = ground truth in the map frame (origin = start pose)
    plus a small seeded drift."""
    rng = np.random.default_rng([index, len(world)])
    t = np.arange(1, 201) * 0.1
    angle = np.linspace(0, 2 * np.pi, len(t))
    local = np.column_stack([1.5 * np.sin(angle), 1.0 - np.cos(angle), angle])
    world_T_map = np.array(START[world])
    gt = compose(world_T_map, local)
    slam = compose(inverse(world_T_map), gt) + np.cumsum(rng.normal(0, 1e-3, (len(t), 3)), 0)
    return rec.Trajectories(t, gt, slam, slam.copy())


def occupancy(shape=(60, 80)) -> np.ndarray:
    """An OccupancyGrid (row 0 = bottom): unknown border, free room, walls around it."""
    grid = np.full(shape, -1, np.int8)
    grid[10:50, 10:70] = 100
    grid[11:49, 11:69] = 0
    return grid


def run_record(world: str, index: int, trans: float, rot: float) -> dict:
    return {
        "world": world, "world_file": f"worlds/{world}.world", "run_index": index,
        "seed": 1000 + index, "code_version": "0.1.0+test", "config_hashes": HASHES,
        "settings_file": "config/collect.yaml", "odometry_model": "uniform_per_run",
        "stop_reason": "map_converged" if index else "max_sim_time",
        "sim_duration_s": 600.0 + 10 * index, "wall_time_s": 100.0 + index,
        "distance_m": 40.0 + index, "rotation_rad": 20.0 + index, "coverage": 0.9 + 0.01 * index,
        "metric": {"trans_mean": trans, "trans_std": trans / 2, "rot_mean": rot,
                   "rot_std": rot / 2, "trans_sqr_mean": trans ** 2, "trans_sqr_std": 0.0,
                   "rot_sqr_mean": rot ** 2, "rot_sqr_std": 0.0, "n": 100 + index},
    }


def build(root: Path) -> Path:
    """Write the campaign below ``root/data``; returns that folder."""
    data = Path(root) / "data"
    for world, errors in ERRORS.items():
        for index, (trans, rot) in enumerate(errors):
            folder = data / world / f"run_{index:03d}"
            folder.mkdir(parents=True)
            if not (world == "beta" and index == 1):
                rec.write_trajectories(folder, trajectories(world, index))
                rec.write_map(folder, occupancy(), RESOLUTION, MAP_ORIGIN[:2])
            rec.write_run_json(folder, run_record(world, index, trans, rot))
    write_summary(data)
    return data


def copy(data: Path, target: Path) -> Path:
    """A copy of a campaign to damage in a test."""
    shutil.copytree(data, target)
    return target
