"""The full feature vector of a World: ``compute_features(world, config) -> {name: value}``.

Four families are registered in :data:`REGISTRY` (in this order): ``geometric``,
``topological``, ``voronoi_graph`` and ``voronoi_traversal``. They share one
:class:`Context`, which computes the interior/Voronoi skeleton, the rooms, the topological and
Voronoi graphs and the traversal once, lazily.

Every feature is computed on a working grid of ``working_resolution_m`` (0.1 m/px): plans with
finer pixels are resampled conservatively (a cell is an obstacle if any source pixel in it is),
so that a building gives the same features whatever resolution it was drawn or loaded at, and
large plans stay fast. Coarser plans are used as they are; 0 disables the resampling.

The traversal features are the mean over ``grid_phases`` (4) phases of the working grid
(:func:`phase_worlds`: as is, and resampled onto the lattice shifted by half a cell along
both axes, rows, columns). On one grid the traversal moves by more than 5 % under a 5 cm
shift of the plan on a third of the thesis layouts (the greedy tour amplifies one-cell
differences of the Voronoi graph into another visiting order), which is most of what made
the same building at 0.05 and 0.10 m/px disagree; the mean is steadier. Rooms, the graphs
and the output path come from the unshifted grid.

When the start cell lies outside the building outline (a door drawn closed, the start in the
smaller part), only the free space connected to the start is used (:func:`start_outline`); no
thesis, shipped or ipa plan is affected.

``FeaturesConfig.mode = "thesis_compatible"`` switches the Voronoi graph and the traversal to
the seed code's behaviour (see :mod:`traversal`); ``FEATURE_VERSION`` changes whenever a
feature's definition does, and :func:`feature_version` adds the configuration hash.
"""
from __future__ import annotations

import dataclasses
import logging
import math
import time
from dataclasses import dataclass, field
from functools import cached_property
from typing import ClassVar

import numpy as np
from scipy import ndimage

from slam_predict.config import NON_NEGATIVE, Range, config_hash, to_dict
from slam_predict.features import geometric, graph_metrics
from slam_predict.features import rooms as rooms_mod
from slam_predict.features import topology as topology_mod
from slam_predict.features import traversal as traversal_mod
from slam_predict.features import voronoi as voronoi_mod
from slam_predict.features.registry import Registry
from slam_predict.world.bitmap import resample_square
from slam_predict.world.model import World

LOG = logging.getLogger(__name__)
PROGRESS = logging.getLogger("slam_predict.features.progress")  # shown by the CLI on a TTY
FEATURE_VERSION = "2"  # 2: rooms on a fixed 0.2 m grid, traversal averaged over 4 grid phases
MODES = traversal_mod.MODES
FAMILIES = ("geometric", "topological", "voronoi_graph", "voronoi_traversal")


@dataclass(frozen=True)
class FeaturesConfig:
    """Everything the feature extractor reads from ``config/features.yaml``."""

    mode: str = "documented"
    working_resolution_m: float = 0.1
    grid_phases: int = 4
    families: tuple[str, ...] = FAMILIES
    rooms: rooms_mod.RoomsConfig = field(default_factory=rooms_mod.RoomsConfig)
    topology: topology_mod.TopologyConfig = field(default_factory=topology_mod.TopologyConfig)
    geometry: geometric.GeometryConfig = field(default_factory=geometric.GeometryConfig)
    voronoi: voronoi_mod.VoronoiConfig = field(default_factory=voronoi_mod.VoronoiConfig)
    traversal: traversal_mod.TraversalConfig = field(
        default_factory=traversal_mod.TraversalConfig)
    RANGES: ClassVar[dict[str, Range]] = {"working_resolution_m": NON_NEGATIVE}

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise ValueError(f"mode must be one of {', '.join(MODES)}, got {self.mode!r}")
        for name in self.families:
            REGISTRY.family(name)
        if self.grid_phases not in (1, 2, 4):
            raise ValueError(f"grid_phases must be 1, 2 or 4, got {self.grid_phases}")
        if self.working_resolution_m < 0:
            raise ValueError("working_resolution_m must be ≥ 0 (0 = the map's own)")

    def voronoi_config(self) -> voronoi_mod.VoronoiConfig:
        """Voronoi settings with the mode applied."""
        return dataclasses.replace(self.voronoi,
                                   thesis_compatible=self.mode == "thesis_compatible")

    def traversal_config(self) -> traversal_mod.TraversalConfig:
        """Traversal settings with the mode applied."""
        return dataclasses.replace(self.traversal, mode=self.mode)


def working_world(world: World, resolution: float) -> World:
    """``world`` on a grid of ``resolution`` m/px when its own pixels are finer (obstacle where
    any source pixel is, :func:`bitmap.resample_square`); unchanged otherwise or when 0."""
    if resolution <= 0 or world.resolution >= resolution * (1 - 1e-6):
        return world
    occupied = resample_square(world.occupied, world.size_m, resolution)
    return world.replace(occupied=occupied, resolution=resolution)


def start_outline(world: World) -> World:
    """``world`` itself when its start cell lies inside the building outline (the longest
    contour of the free space, :func:`voronoi.building_interior`); else ``world`` with only the
    free space 8-connected to the start cell, so that the outline, rooms, graphs and traversal
    are those of the part the robot starts in (a door drawn closed left the start outside the
    largest part, and every feature described a part the robot never enters)."""
    free = ~world.occupied
    row, col = world.world_to_cell(world.start_pose[:2])
    if not world.in_bounds((row, col)) or not free[row, col]:
        return world
    if voronoi_mod.building_interior(free)[row, col]:
        return world
    labels, _ = ndimage.label(free, structure=np.ones((3, 3), bool))
    LOG.info("%s: the start (%.2f, %.2f) m lies outside the largest part of the plan: "
             "features of the part it lies in", world.name, *world.start_pose[:2])
    return world.replace(occupied=labels != labels[row, col])


def phase_worlds(world: World, count: int = 4) -> list[World]:
    """``world`` (on its working grid) and up to three copies on the grid shifted by half a
    cell: along rows and columns, along rows only, along columns only (``count`` = 1, 2 or 4
    grids in all). A shifted grid is the conservative resample of the working grid onto the
    shifted lattice: each new cell is an obstacle when either of the two (or four) cells it
    overlaps is (border cells repeated), so it has one more row / column, the same centre
    (origin) and walls one cell thicker along the shifted axes."""
    out = [world]
    for axes in ((0, 1), (0,), (1,))[:count - 1]:
        occupied = world.occupied
        for axis in axes:
            edged = np.concatenate([occupied.take([0], axis), occupied,
                                    occupied.take([-1], axis)], axis=axis)
            occupied = edged.take(range(edged.shape[axis] - 1), axis) | \
                edged.take(range(1, edged.shape[axis]), axis)
        out.append(world.replace(occupied=occupied))
    return out


class Context:
    """Intermediate products of one World (on the working grid), computed on first use."""

    def __init__(self, world: World, config: FeaturesConfig):
        self.source = world
        self.world = start_outline(working_world(world, config.working_resolution_m))
        self.config = config

    @cached_property
    def skeleton(self) -> voronoi_mod.Skeleton:
        """Interior, feature transform and cleaned Voronoi skeleton."""
        return voronoi_mod.skeleton_of(self.world.occupied, self.world.resolution,
                                   self.config.voronoi_config())

    @cached_property
    def rooms(self) -> rooms_mod.Rooms:
        """Room segmentation (or ground truth)."""
        return rooms_mod.rooms_of(self.world, self.config.rooms, self.skeleton)

    @cached_property
    def topology(self) -> topology_mod.TopologyGraph:
        """Room graph."""
        return topology_mod.topology_graph(self.rooms, self.config.topology)

    @cached_property
    def voronoi(self) -> voronoi_mod.VoronoiGraph:
        """Sparsified Voronoi graph."""
        return voronoi_mod.voronoi_graph(self.world.occupied, self.world.resolution,
                                     self.config.voronoi_config(), self.skeleton)

    @cached_property
    def traversal(self) -> traversal_mod.TraversalResult:
        """Voronoi traversal from the world's start pose."""
        start = self.world.world_to_cell(self.world.start_pose[:2])
        return traversal_mod.traverse(self.voronoi, self.world.occupied, start,
                                  float(self.world.start_pose[2]),
                                  self.config.traversal_config())

    @cached_property
    def phase_traversals(self) -> list[traversal_mod.TraversalResult]:
        """The traversal at every phase of :func:`phase_worlds` (the first is
        :attr:`traversal`)."""
        results = [self.traversal]
        vconfig = self.config.voronoi_config()
        for k, world in enumerate(phase_worlds(self.world, self.config.grid_phases)[1:]):
            PROGRESS.info("%s: traversal on shifted grid %d/%d", self.source.name, k + 1,
                          self.config.grid_phases - 1)
            graph = voronoi_mod.voronoi_graph(world.occupied, world.resolution, vconfig)
            start = world.world_to_cell(world.start_pose[:2])
            results.append(traversal_mod.traverse(graph, world.occupied, start,
                                                  float(world.start_pose[2]),
                                                  self.config.traversal_config()))
        return results

    def path_xy(self) -> np.ndarray:
        """The traversal path as (K, 2) world coordinates, m."""
        return self.world.cell_to_world(self.traversal.path_rc)


def _geometric(ctx: Context) -> dict[str, float]:
    return geometric.geometric_features(ctx.skeleton.interior, ctx.rooms,
                                        ctx.world.resolution, ctx.config.geometry)


def _prefixed(prefix: str, values: dict[str, float]) -> dict[str, float]:
    return {f"{prefix}_{k}": v for k, v in values.items()}


def _topological(ctx: Context) -> dict[str, float]:
    return _prefixed("topology", topology_mod.topology_metrics(ctx.topology))


def _voronoi_graph(ctx: Context) -> dict[str, float]:
    graph = ctx.voronoi
    return _prefixed("voronoi", graph_metrics.metrics(graph.order, graph.edges))


def _voronoi_traversal(ctx: Context) -> dict[str, float]:
    results = ctx.phase_traversals
    return {"voronoi_traversal_distance": float(np.mean([r.distance for r in results])),
            "voronoi_traversal_rotation": float(np.mean([r.rotation for r in results])),
            "voronoi_traversal_rotation_smoothed":
                float(np.mean([r.rotation_smoothed for r in results]))}


def _graph_features(prefix: str, what: str):
    return [(f"{prefix}_{name}", unit, f"{what}: {doc}")
            for name, unit, doc in graph_metrics.METRICS]


REGISTRY = Registry()
REGISTRY.add_family("geometric", _geometric, geometric.FEATURES)
REGISTRY.add_family("topological", _topological,
                    _graph_features("topology", "room graph (largest component)"))
REGISTRY.add_family("voronoi_graph", _voronoi_graph,
                    _graph_features("voronoi", "sparsified Voronoi graph"))
REGISTRY.add_family("voronoi_traversal", _voronoi_traversal, (
    ("voronoi_traversal_distance", "m",
     "length of the simulated exploration path on the Voronoi graph (Algorithms 3–4)"),
    ("voronoi_traversal_rotation", "rad",
     "summed |heading change| along that path between points > 0.5 m apart"),
    ("voronoi_traversal_rotation_smoothed", "rad",
     "summed |turn| of the path simplified by Douglas–Peucker (smoothing_tolerance_m)"),
))


def feature_version(config: FeaturesConfig | None = None) -> str:
    """``<FEATURE_VERSION>+<config hash>``: equal strings mean comparable feature vectors."""
    plain = to_dict(config or FeaturesConfig())
    plain["traversal"] = traversal_mod.legacy_hash_form(plain["traversal"])
    return f"{FEATURE_VERSION}+{config_hash(plain)}"


def compute_with_context(world: World, config: FeaturesConfig | None = None
                         ) -> tuple[dict[str, float], Context]:
    """The flat feature vector and the :class:`Context` holding rooms, graphs and the path."""
    config = config or FeaturesConfig()
    start = time.monotonic()
    ctx = Context(world, config)
    rows, cols = ctx.world.occupied.shape
    values: dict[str, float] = {}
    for i, name in enumerate(config.families):
        PROGRESS.info("%s: %s features (%d/%d, %d x %d px working grid, %.0f s so far)",
                      world.name, name, i + 1, len(config.families), cols, rows,
                      time.monotonic() - start)
        family = REGISTRY.family(name)
        out = family.compute(ctx)
        expected = [f.name for f in family.features]
        if list(out) != expected:
            raise RuntimeError(f"family {name} returned {sorted(out)}, expected {expected}")
        values.update({k: float(v) for k, v in out.items()})
    bad = [k for k, v in values.items() if not math.isfinite(v)]
    if bad:
        LOG.warning("%s: non-finite features %s", world.name, ", ".join(bad))
    return values, ctx


def degenerate_reason(values: dict[str, float]) -> str | None:
    """Why a feature vector describes no building (None when it does): no Voronoi graph or
    no room was found (random noise, free space too narrow for the working grid)."""
    missing = [what for key, what in (("voronoi_order", "no Voronoi graph"),
                                      ("num_spaces", "no rooms"))
               if key in values and not values[key] > 0]
    if not missing:
        return None
    return (" and ".join(missing) + " could be extracted: not a building floor plan (noise, "
            "or free space too narrow or fragmented)")


def compute_features(world: World, config: FeaturesConfig | None = None) -> dict[str, float]:
    """The flat feature vector {name: value} of ``world`` (units in :data:`REGISTRY`)."""
    return compute_with_context(world, config)[0]
