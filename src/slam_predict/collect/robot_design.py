"""A space-filling design of robot configurations over buildings (issue #18's campaign).

A design is a YAML file (``slam-predict design``, then ``collect --design FILE``):

- ``configs``: robot configurations ``c00, c01, …`` from a maximin Latin hypercube over the
  ``factors`` (laser ``range_max`` m, ``fov`` deg, and the odometry error bounds as multiples of
  the base robot's: x/y and yaw scales); the range is spread evenly in log(range), where the
  error changes most (3.5–7 m gets as many configurations as 15–30 m);
- ``worlds``: for every building, the configurations it is explored with (``points_per_world``
  distinct ones, each building taking the least-used so far with random tie-breaks, so every
  configuration is used on ⌊W·P/C⌋ or ⌈W·P/C⌉ buildings and the sets vary);
- ``replicates``: runs per building × configuration, with different seeds.

Run ``i`` of a building is point ``i mod P`` of its list, replicate ``i div P``: the batch's
index-major order therefore does every building's first replicate of every point before any
second one. Every other robot property (body, speeds, laser rate, range_min, mounting) is the
base robot's; the beams are ``fov / resolution_deg + 1`` (Stage's beam rule).
"""
from __future__ import annotations

import dataclasses
import logging
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import yaml

from slam_predict.atomic import write_text
from slam_predict.config import from_dict, load_yaml, to_dict
from slam_predict.errors import InputError, require_file
from slam_predict.robot_checks import implausible_laser
from slam_predict.robot_file import RobotDescription

FACTORS = ("range_max", "fov", "odom_xy_scale", "odom_yaw_scale")
UNITS = {"range_max": "m", "fov": "deg", "odom_xy_scale": "x base", "odom_yaw_scale": "x base"}
DEFAULT_BOUNDS = {"range_max": (3.5, 30.0), "fov": (180.0, 360.0),
                  "odom_xy_scale": (0.0, 2.0), "odom_yaw_scale": (0.0, 2.0)}
LOG = logging.getLogger(__name__)
LOG_FACTORS = ("range_max",)   # spread evenly in log space
CANDIDATES = 200   # Latin hypercubes drawn; the one with the largest smallest distance is kept
DESIGN_KIND = "robots"


def latin_hypercube(n: int, dims: int, rng: np.random.Generator) -> np.ndarray:
    """An n × dims Latin hypercube in [0, 1): every column has one point in each of the n
    strata [k/n, (k+1)/n), at a uniform position within it."""
    strata = np.stack([rng.permutation(n) for _ in range(dims)], axis=1)
    return (strata + rng.random((n, dims))) / n


def min_distance(points: np.ndarray) -> float:
    """Smallest pairwise Euclidean distance between rows (inf for fewer than two)."""
    if len(points) < 2:
        return math.inf
    diff = points[:, None, :] - points[None, :, :]
    dist = np.sqrt((diff ** 2).sum(axis=2))
    return float(dist[np.triu_indices(len(points), 1)].min())


def maximin_hypercube(n: int, dims: int, rng: np.random.Generator,
                      candidates: int = CANDIDATES) -> np.ndarray:
    """The Latin hypercube with the largest smallest pairwise distance among ``candidates``."""
    best, best_d = None, -1.0
    for _ in range(candidates):
        points = latin_hypercube(n, dims, rng)
        d = min_distance(points)
        if d > best_d:
            best, best_d = points, d
    return best


def deal(worlds: Sequence[str], configs: Sequence[str], per_world: int,
         rng: np.random.Generator) -> dict[str, list[str]]:
    """Give each world ``per_world`` distinct configurations: worlds in shuffled order each take
    the least-used configurations so far, ties broken at random. Use counts never differ by
    more than 1, and the random tie-breaks keep the worlds' sets from repeating in blocks."""
    if not 1 <= per_world <= len(configs):
        raise ValueError(f"points per world must be in 1..{len(configs)}, got {per_world}")
    uses = dict.fromkeys(configs, 0)
    dealt = {}
    for index in rng.permutation(len(worlds)):
        shuffled = [configs[i] for i in rng.permutation(len(configs))]
        chosen = sorted(shuffled, key=uses.__getitem__)[:per_world]   # stable: ties random
        for config in chosen:
            uses[config] += 1
        dealt[worlds[index]] = chosen
    return {world: dealt[world] for world in worlds}


@dataclass(frozen=True)
class RobotDesign:
    """A design (see the module docstring); ``configs`` maps id → factor values."""

    base: RobotDescription
    bounds: dict[str, tuple[float, float]]
    resolution_deg: float
    configs: dict[str, dict[str, float]]
    worlds: dict[str, list[str]]
    replicates: int
    seed: int

    def __post_init__(self) -> None:
        for config in self.configs:
            self.robot(config)   # ValueError unless every configuration makes a valid robot

    @property
    def points_per_world(self) -> int:
        return len(next(iter(self.worlds.values())))

    @property
    def runs_per_world(self) -> int:
        return self.points_per_world * self.replicates

    def run_point(self, world: str, index: int) -> dict[str, Any]:
        """Design entry of run ``index`` of ``world``: config id, point, replicate, factors."""
        if world not in self.worlds:
            raise KeyError(f"world '{world}' is not in the design")
        per = self.points_per_world
        if not 0 <= index < self.runs_per_world:
            raise KeyError(f"run {index} of '{world}' is beyond the design's {self.runs_per_world}")
        config = self.worlds[world][index % per]
        return {"config": config, "point": f"{world}/{config}", "replicate": index // per,
                **self.configs[config]}

    def robot(self, config: str) -> RobotDescription:
        """The robot description of configuration ``config``."""
        return configured_robot(self.base, self.configs[config], self.resolution_deg, config)

    def settings_for(self, settings, config: str, path: os.PathLike | str):
        """Collection ``settings`` with configuration ``config``'s robot (``path``: this
        design's file, named in errors)."""
        from slam_predict.collect.settings import with_robot

        return with_robot(settings, self.robot(config), str(path))

    def run_hashes(self, settings, path: os.PathLike | str):
        """(world, run index) → the config hashes of that run's settings (None for a run
        the design does not have); hashes computed once per configuration."""
        cache: dict[str, dict[str, str]] = {}

        def hashes(world: str, index: int) -> dict[str, str] | None:
            try:
                config = self.run_point(world, index)["config"]
            except KeyError:
                return None
            if config not in cache:
                cache[config] = self.settings_for(settings, config, path).hashes()
            return cache[config]

        return hashes


def configured_robot(base: RobotDescription, factors: Mapping[str, float],
                     resolution_deg: float, name: str) -> RobotDescription:
    """``base`` with the laser range and fov of ``factors``, fov/resolution + 1 beams, and its
    odometry error bounds scaled (x and y by odom_xy_scale, yaw by odom_yaw_scale)."""
    fov = float(factors["fov"])
    samples = int(round(fov / resolution_deg)) + 1
    laser = dataclasses.replace(base.laser, range_max=float(factors["range_max"]), fov=fov,
                                samples=samples)
    x, y, yaw = base.odom_error
    xy, rot = float(factors["odom_xy_scale"]), float(factors["odom_yaw_scale"])
    return dataclasses.replace(base, name=f"{base.name}-{name}", laser=laser,
                               odom_error=(x * xy, y * xy, yaw * rot),
                               description=f"design configuration {name} of {base.name}")


def implausible_configs(design: RobotDesign) -> list[tuple[str, str, str]]:
    """(configuration, key, sentence) for each laser no real robot has among ``design``'s
    configurations (:func:`~slam_predict.robot_checks.implausible_laser`: usually bounds in
    radians or millimetres, or a coarse resolution), in configuration order. The odometry is
    not checked: its factors are multiples of the base robot's, whose file was checked."""
    return [(config, key, sentence) for config in design.configs
            for key, sentence in implausible_laser(design.robot(config))]


def check_plausible(design: RobotDesign, force: bool, where: os.PathLike | str | None = None,
                    sources: Mapping[str, str] | None = None) -> None:
    """InputError (naming ``where``) on the first implausible configuration of ``design``
    (:func:`implausible_configs`), unless ``force``: then each is logged. ``sources`` maps a
    key (``laser.fov``) to the input it came from (``--fov 3 6.28``), named in the message."""
    sources = sources or {}
    problems = [f"configuration {config}: {sentence}"
                + (f" (from {sources[key]})" if key in sources else "")
                for config, key, sentence in implausible_configs(design)]
    if problems and not force:
        more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
        raise InputError(f"{problems[0]}{more}; --force uses it as written", where)
    for problem in problems:
        LOG.warning("%s: %s (used as written: --force)", where or "design", problem)


def scaled(factor: str, u: float, bounds: tuple[float, float]) -> float:
    """The value at fraction ``u`` of ``factor``'s bounds (in log space for LOG_FACTORS)."""
    low, high = bounds
    if factor in LOG_FACTORS and low > 0:
        return math.exp(math.log(low) + u * (math.log(high) - math.log(low)))
    return low + u * (high - low)


def make_design(worlds: Sequence[str], base: RobotDescription, n_configs: int,
                points_per_world: int, replicates: int, seed: int,
                bounds: Mapping[str, tuple[float, float]] = DEFAULT_BOUNDS,
                resolution_deg: float = 0.5) -> RobotDesign:
    """A new design: maximin LHS of ``n_configs`` configurations dealt over ``worlds``."""
    if n_configs < 1 or replicates < 1 or not worlds:
        raise ValueError("a design needs >= 1 configuration, >= 1 replicate and >= 1 world")
    rng = np.random.default_rng(seed)
    unit = maximin_hypercube(n_configs, len(FACTORS), rng)
    configs = {f"c{k:02d}": {name: float(round(scaled(name, u, bounds[name]), 4))
                             for name, u in zip(FACTORS, row, strict=True)}
               for k, row in enumerate(unit)}
    dealt = deal(list(worlds), list(configs), points_per_world, rng)
    return RobotDesign(base, {f: tuple(bounds[f]) for f in FACTORS}, float(resolution_deg),
                       configs, dealt, int(replicates), int(seed))


def design_dict(design: RobotDesign) -> dict[str, Any]:
    """The YAML content of ``design``."""
    base = to_dict(design.base)
    return {"kind": DESIGN_KIND, "seed": design.seed, "replicates": design.replicates,
            "resolution_deg": design.resolution_deg,
            "bounds": {f: list(b) for f, b in design.bounds.items()},
            "base_robot": base, "configs": design.configs, "worlds": design.worlds}


def write_design(design: RobotDesign, path: os.PathLike | str) -> None:
    """Write ``design`` as YAML (atomically)."""
    header = ("# Robot-configuration design (slam-predict design); run i of a building "
              "is point i mod P of its list, replicate i div P.\n")
    write_text(path, header + yaml.safe_dump(design_dict(design), sort_keys=False))


def load_design(path: os.PathLike | str) -> RobotDesign:
    """Read and check a design file; InputError (one line, naming the file) on any problem."""
    path = require_file(path, "design file")
    data = load_yaml(path)
    if data.get("kind") != DESIGN_KIND:
        raise InputError(f"not a robot design (kind: {data.get('kind')!r}, expected "
                         f"'{DESIGN_KIND}')", path)
    try:
        return _design_from(data, path)
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(f"bad design: {exc}", path) from None


def _design_from(data: Mapping[str, Any], path: str) -> RobotDesign:
    base = from_dict(RobotDescription, data["base_robot"], path, "base_robot")
    configs = {str(k): {f: float(v[f]) for f in FACTORS} for k, v in data["configs"].items()}
    worlds = {str(w): [str(c) for c in cs] for w, cs in data["worlds"].items()}
    sizes = {len(cs) for cs in worlds.values()}
    if len(sizes) != 1 or 0 in sizes:
        raise ValueError("every world must list the same, non-zero number of configurations")
    for world, cs in worlds.items():
        unknown = sorted(set(cs) - set(configs))
        if unknown or len(set(cs)) != len(cs):
            raise ValueError(f"world '{world}' lists unknown or repeated configurations")
    return RobotDesign(base, {f: tuple(data["bounds"][f]) for f in FACTORS},
                       float(data["resolution_deg"]), configs, worlds,
                       int(data["replicates"]), int(data["seed"]))
