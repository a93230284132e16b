"""A synthetic robot campaign with a known truth, written as run.json files (tests only).

Ground truth of a run's mean translational error (m)::

    ε_t = 0.004 · area^0.5 · (range / 10)^-0.3 · (fov / 270)^-0.2 · (1 + 40·xy + 8·yaw) · u

with u lognormal of mean 1 and log-sd σ(yaw) = 0.08 + 2·yaw (heteroscedastic: 0.08–0.22);
the rotational error (rad) is 0.002 · area^0.25 · (1 + 15·yaw) · u' (u' as u, independent).
The design draws robots like the real one: a Latin hypercube over range 3.5–30 m, fov
180–360°, odometry bound scales 0–2 × (0.01 m/m, 0.0349 rad/rad); 0.5° beams. Records name
config/collect.yaml as their settings (GMapping maxUrange 30 m) with the GMapping config hash
the collection would record for their laser; :func:`write_design` writes the design file of
a campaign's robots and :func:`train_model` a model folder (also used by
bench/bench_predict_robot.py, which imports this module by path).
"""
from __future__ import annotations

import csv
import functools
import json
import math
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
SETTINGS = "config/collect.yaml"   # relative to the project root, as run.json records it
SEED_ROBOT = ROOT / "config" / "robots" / "seed_realistic.yaml"
YAW = 2.0 * math.pi / 180.0   # 2 °/rad in rad/rad
FEATURES = ("building_area", "building_perimeter", "voronoi_traversal_distance",
            "voronoi_traversal_rotation", "junk")


def latin_hypercube(n: int, rng: np.random.Generator) -> np.ndarray:
    """(n, 4) points in [0, 1)^4, one per row stratum in every column."""
    strata = np.stack([rng.permutation(n) for _ in range(4)], axis=1)
    return (strata + rng.random((n, 4))) / n


def robot_configs(n: int, rng: np.random.Generator) -> list[dict]:
    """n robots: range_max m, fov deg, odom xy m/m, odom yaw rad/rad."""
    u = latin_hypercube(n, rng)
    return [{"range_max": 3.5 + 26.5 * a, "fov": 180.0 + 180.0 * b, "xy": 0.02 * c,
             "yaw": 2.0 * YAW * d} for a, b, c, d in u]


def buildings(n: int, rng: np.random.Generator, prefix: str = "w") -> dict[str, dict]:
    """n buildings: plan features (area m², perimeter m, traversal m and rad, junk)."""
    out = {}
    for i in range(n):
        area = float(np.exp(rng.uniform(np.log(150), np.log(3000))))
        out[f"{prefix}{i:02d}"] = {
            "building_area": area,
            "building_perimeter": 4.0 * math.sqrt(area) * rng.uniform(1.0, 1.6),
            "voronoi_traversal_distance": 0.4 * area * rng.uniform(0.8, 1.2),
            "voronoi_traversal_rotation": 0.05 * area * rng.uniform(0.8, 1.2),
            "junk": float(rng.normal()), **sightline_curve(area)}
    return out


def sightline_curve(area: float) -> dict[str, float]:
    """A plan's sight-line curve columns (features/sightline.py): the blind fraction at range
    r is exp(−(r / L)^1.5) with L = √area / 4 m (larger buildings, longer sight lines)."""
    from slam_predict.features.sightline import CURVE_RANGES_M, curve_columns

    scale = math.sqrt(area) / 4.0
    return {name: math.exp(-(r / scale) ** 1.5)
            for name, r in zip(curve_columns(), CURVE_RANGES_M, strict=True)}


def sigma(robot: dict) -> float:
    """Log-sd of a run's error around its expectation."""
    return 0.08 + 2.0 * robot["yaw"]


def expected(features: dict, robot: dict) -> tuple[float, float]:
    """Noise-free (expected) trans_mean m and rot_mean rad of a run; a robot with a
    ``resolution`` (deg between beams, default 0.5) other than 0.5 errs as (res / 0.5)^-0.3
    (finer beams, more compute, more dropped scans: as measured on the resolution campaigns)."""
    area = features["building_area"]
    beams = (robot.get("resolution", 0.5) / 0.5) ** -0.3
    trans = (0.004 * math.sqrt(area) * (robot["range_max"] / 10.0) ** -0.3 * beams
             * (robot["fov"] / 270.0) ** -0.2 * (1.0 + 40.0 * robot["xy"] + 8.0 * robot["yaw"]))
    rot = 0.002 * area ** 0.25 * (1.0 + 15.0 * robot["yaw"]) * beams
    return trans, rot


def draw(features: dict, robot: dict, rng: np.random.Generator) -> tuple[float, float]:
    """One run's (trans_mean, rot_mean): the expectation times mean-one lognormal noise."""
    s = sigma(robot)
    trans, rot = expected(features, robot)
    u = np.exp(s * rng.normal(size=2) - s * s / 2.0)
    return trans * float(u[0]), rot * float(u[1])


def sensor(robot: dict) -> dict:
    """run.json's ``sensor`` of a robot (fov rad, ``resolution`` deg beams, default 0.5°)."""
    resolution = robot.get("resolution", 0.5)
    return {"laser": {"fov": math.radians(robot["fov"]), "range_max": robot["range_max"],
                      "range_min": 0.0, "samples": int(round(robot["fov"] / resolution)) + 1,
                      "rate_hz": 10.0, "pose": [0.0, 0.0, 0.0], "noise_std": 0.0},
            "odom": {"error": [robot["xy"], robot["xy"], robot["yaw"]],
                     "model": "uniform_per_run", "gaussian": [0.005, 0.005, 0.01, 0.002]}}


@functools.lru_cache(maxsize=1)
def _gmapping_params():
    from slam_predict.collect.settings import load_settings

    return load_settings(ROOT / SETTINGS).slam.params


@functools.lru_cache(maxsize=256)
def gmapping_hash(range_max: float) -> str:
    """The GMapping config hash a run with this laser records under the default settings."""
    from slam_predict.config import config_hash
    from slam_predict.robot_file import gmapping_caps

    return config_hash(gmapping_caps(_gmapping_params(), range_max))


def record(world: str, index: int, seed: int, robot: dict, errors: tuple[float, float],
           design: dict | None, coverage: float = 0.99) -> dict:
    """A run.json dict as the campaign writes it."""
    gmapping = gmapping_hash(robot["range_max"])
    out = {"world": world, "run_index": index, "seed": seed, "free_area_m2": 500.0,
           "coverage": coverage, "stop_reason": "map_converged", "distance_m": 300.0,
           "sensor": sensor(robot),
           "odometry_error": {"bias": [0.0, 0.0, 0.0], "bound": sensor(robot)["odom"]["error"],
                              "model": "uniform_per_run"},
           "metric": {"trans_mean": errors[0], "rot_mean": errors[1], "trans_std": 0.1,
                      "rot_std": 0.01},
           "config_hashes": {"gmapping": gmapping, "sim": "s1"}, "code_version": "0.1.0+test",
           "settings_file": SETTINGS, "slam": {"type": "gmapping", "params_hash": gmapping}}
    if design is not None:
        out["design"] = design
    return out


def write_campaign(folder: Path, worlds: dict[str, dict], robots: list[dict], replicates: int,
                   rng: np.random.Generator, design: bool = True) -> list[dict]:
    """Write ``folder/<world>/run_NNN/run.json`` for every world × robot × replicate; returns
    the records written (with ``path``)."""
    written = []
    for world, features in worlds.items():
        index = 0
        for c, robot in enumerate(robots):
            for r in range(replicates):
                tag = {"config": f"c{c:02d}", "point": f"{world}/c{c:02d}", "replicate": r}
                rec = record(world, index, int(rng.integers(2 ** 31)), robot,
                             draw(features, robot, rng), tag if design else None)
                path = folder / world / f"run_{index:03d}" / "run.json"
                path.parent.mkdir(parents=True)
                path.write_text(json.dumps(rec))
                written.append(dict(rec, path=str(path)))
                index += 1
    return written


def write_features(path: Path, worlds: dict[str, dict], version: str = "synthetic-v1") -> Path:
    """The feature table (world, feature_version, features, sight-line curve)."""
    from slam_predict.features.sightline import curve_columns

    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        columns = [*FEATURES, *curve_columns()]
        writer.writerow(["world", "feature_version", *columns])
        for world, values in worlds.items():
            writer.writerow([world, version, *(repr(values[f]) for f in columns)])
    return path


def campaign(folder: Path, n_worlds: int = 12, n_configs: int = 6, replicates: int = 2,
             seed: int = 0) -> tuple[dict, list[dict], list[dict]]:
    """(worlds, robots, records) of a synthetic campaign written under ``folder``."""
    rng = np.random.default_rng(seed)
    worlds = buildings(n_worlds, rng)
    robots = robot_configs(n_configs, rng)
    records = write_campaign(folder, worlds, robots, replicates, rng)
    return worlds, robots, records


FAST_FEATURES = ("building_area", "building_perimeter", "voronoi_traversal_distance",
                 "voronoi_traversal_rotation")   # the synthetic plans' features (no sight lines)
FAST = {"conformal_folds": 3, "folds": 3, "plan_features": list(FAST_FEATURES),
        "elasticnet": {"alphas": [0.001, 0.01, 0.1], "l1_ratios": [0.5, 1.0], "cv": 3},
        "gradient_boosting": {"n_estimators": 60, "learning_rate": 0.1, "max_depth": 2},
        "trend_boosting": {"n_estimators": 60, "learning_rate": 0.1, "max_depth": 2}}


def fast_config(**changes):
    """A RobotLearningConfig with small grids and few folds (tests)."""
    from slam_predict.config import from_dict
    from slam_predict.learn.robot.config import RobotLearningConfig

    return from_dict(RobotLearningConfig, {**FAST, **changes}, "test")


def load(folder: Path, worlds: dict[str, dict], version: str = "synthetic-v1"):
    """The RunData of a synthetic campaign folder with its true plan features (runs
    skipped by the failed-exploration rule, ``metric.runs.MIN_COVERAGE``)."""
    from slam_predict.learn.robot.records import read_runs
    from slam_predict.learn.robot.rundata import build_run_data

    runs, skipped = read_runs([folder])
    features = {w: {k: v for k, v in f.items()} for w, f in worlds.items()}
    return build_run_data(runs, skipped, features, version)


def true_point_values(data, worlds: dict[str, dict], robots: list[dict]) -> dict:
    """Noise-free POINT values: expected trans_mean m and the runs' true trans std m."""
    mean, std = [], []
    points = data.point_dataset()
    for world, config in zip(points.worlds, points.robot, strict=True):
        robot = robots[int(config[1:])]
        trans = expected(worlds[world], robot)[0]
        s = sigma(robot)
        mean.append(trans)
        std.append(trans * math.sqrt(math.exp(s * s) - 1.0))
    return {"trans_mean": np.array(mean), "trans_std": np.array(std)}


def write_design(path: Path, worlds: dict[str, dict], robots: list[dict],
                 replicates: int = 2) -> Path:
    """The design file (``slam-predict design``'s format) of a campaign's robots: base robot
    the seed study's realistic one, configuration ``cNN`` = robot NN, every world all of them."""
    from slam_predict.collect.robot_design import DEFAULT_BOUNDS, RobotDesign, write_design
    from slam_predict.robot_file import load_robot

    configs = {f"c{c:02d}": {"range_max": float(r["range_max"]), "fov": float(r["fov"]),
                             "odom_xy_scale": float(r["xy"] / 0.01),
                             "odom_yaw_scale": float(r["yaw"] / YAW)}
               for c, r in enumerate(robots)}
    design = RobotDesign(load_robot(SEED_ROBOT), dict(DEFAULT_BOUNDS), 0.5, configs,
                         {w: list(configs) for w in worlds}, replicates, 0)
    write_design(design, path)
    return path


# Best model per component of the test models (the fast ones: a Gaussian process takes
# seconds per fit; tests/learn/test_robot_plain.py checks its plain form on its own).
BEST = {"trans_mean": "gradient_boosting", "trans_std": "elasticnet",
        "rot_mean": "gradient_boosting", "rot_std": "elasticnet"}


def train_model(folder: Path, name: str = "own-robots", config=None, best=None,
                n_worlds: int = 12, n_configs: int = 6) -> Path:
    """``folder/models/<name>``: a robot-aware model folder trained on a synthetic campaign
    written under ``folder`` (with its design file), whose card names this installation's
    default feature configuration and version, so that ``predict --robot`` can use it on real
    plans (the numbers mean nothing there). ``config``: a RobotLearningConfig (default
    :func:`fast_config` with elasticnet and gradient boosting); ``best``: component → kind."""
    from slam_predict.features.plan import full_feature_config, version_of
    from slam_predict.learn.robot.domain import design_ranges
    from slam_predict.learn.robot.failure import outcome_runs
    from slam_predict.learn.robot.train import train_robot_store

    worlds, robots, _ = campaign(folder / "data", n_worlds, n_configs)
    design = write_design(folder / "design.yaml", worlds, robots)
    feature_config = full_feature_config({})
    data = load(folder / "data", worlds, version=version_of(feature_config))
    config = config or fast_config(models=["elasticnet", "gradient_boosting"])
    bounds = design_ranges(design, data.max_urange_m, data.configs)
    return train_robot_store(data, config, [], best or BEST, folder / "models" / name,
                             {"name": name, "description": "synthetic test model",
                              "feature_config": feature_config, "design_bounds": bounds,
                              "outcome_runs": outcome_runs([folder / "data"],
                                                           data.max_urange_m)})
