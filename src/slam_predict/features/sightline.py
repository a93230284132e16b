"""Sight lines of a plan: how much of what a laser of a given range sees is a wall (issue #18).

From points on a square grid over the building's interior (``spacing_m`` apart, at least
``clearance_m`` from every obstacle: where a robot can stand), ``beams`` rays evenly spread
over 360° are cast to ``max_range_m`` (exact ray casting, :mod:`slam_predict.sim.raycast`).
The *blind fraction* at range r is the fraction of those sight lines that reach no wall
within r: what a laser of range r returns as no-hit beams, averaged over the floor. A 30 m laser
in a house sees walls in nearly every direction (blind ≈ 0); a 3.5 m laser in a school's halls
is blind in a third of its directions, and GMapping's scan matcher has that much less to
match against.

The plan's *curve* is the blind fraction at the fixed ranges :data:`CURVE_RANGES_M` (columns
:func:`curve_columns`); :func:`blind_fraction` reads it at any range (interpolated linearly in
log range and log fraction, floored at :data:`BLIND_FLOOR`). The robot-aware models take the
blind fraction at the laser's range as an input (:mod:`slam_predict.learn.robot.inputs`).
The same sight lines give the plan feature ``sightline_isotropy``: how evenly the walls a
laser sees face every way (:mod:`slam_predict.features.scan_conditioning`); their floor
points give ``floor_elongation``, how long and thin the floor is
(:mod:`slam_predict.features.floor_shape`). :data:`PLAN_COLUMNS` names these plan features.
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass

import numpy as np

from slam_predict.features.floor_shape import ELONGATION_COLUMN, elongation
from slam_predict.features.scan_conditioning import ISOTROPY_COLUMN, mean_isotropy

BLIND_FLOOR = 1e-3   # fraction: below this a plan is "never blind" (sampling resolution)
CURVE_RANGES_M = tuple(round(1.0 * 40.0 ** (k / 24), 3) for k in range(25))   # 1–40 m, log
COLUMN_PREFIX = "sightline_blind_"
PLAN_COLUMNS = (ISOTROPY_COLUMN, ELONGATION_COLUMN)   # the plan features of this sampling


@dataclass(frozen=True)
class SightlineConfig:
    """Sampling of the sight lines: grid spacing (m), beams per point over 360°, minimum
    clearance of a point from obstacles (m), ray length (m, ≥ the longest curve range), and
    the laser range of the isotropy feature (m: GMapping's maxUrange of the campaigns)."""

    spacing_m: float = 1.0
    beams: int = 360
    clearance_m: float = 0.3
    max_range_m: float = 40.0
    isotropy_range_m: float = 30.0

    def to_dict(self) -> dict:
        return asdict(self)


def curve_columns() -> list[str]:
    """Column names of the curve, one per range of :data:`CURVE_RANGES_M`."""
    return [f"{COLUMN_PREFIX}{r:g}m" for r in CURVE_RANGES_M]


def sample_points(occupied: np.ndarray, resolution: float,
                  config: SightlineConfig) -> tuple[np.ndarray, np.ndarray]:
    """(rows, cols) of the grid points inside the building with the configured clearance:
    one per ``spacing_m`` square, at its centre pixel. The clearance is the distance between
    cell centres to the nearest obstacle, read from the ray caster's cached jump table
    (:func:`slam_predict.sim.raycast.jump_table`: that distance − √2 − 1e-6 cells)."""
    from slam_predict.features.voronoi import building_interior
    from slam_predict.sim.raycast import cached_jump_table

    interior = building_interior(~occupied)
    clearance = (cached_jump_table(occupied) + (math.sqrt(2.0) + 1e-6)) * resolution
    standable = interior & (clearance >= config.clearance_m)
    step = max(1, int(round(config.spacing_m / resolution)))
    rows, cols = np.nonzero(standable[step // 2::step, step // 2::step])
    return rows * step + step // 2, cols * step + step // 2


def sight_lines(world, config: SightlineConfig | None = None) -> np.ndarray:
    """(points, beams) distances to the first wall, m (inf: none within ``max_range_m``),
    from the grid points of :func:`sample_points` of a
    :class:`~slam_predict.world.model.World`."""
    config = config or SightlineConfig()
    rows, cols = sample_points(world.occupied, world.resolution, config)
    return cast_sight_lines(world, rows, cols, config)


def cast_sight_lines(world, rows: np.ndarray, cols: np.ndarray,
                     config: SightlineConfig) -> np.ndarray:
    """:func:`sight_lines` from the given grid points (rows, cols) of ``world``."""
    from slam_predict.sim.raycast import LaserGrid

    grid = LaserGrid.of_world(world)
    frame = grid.frame
    angles = np.arange(config.beams) * (2.0 * math.pi / config.beams)
    cos_a, sin_a = np.cos(angles), np.sin(angles)
    out = np.empty((rows.size, config.beams), dtype=np.float32)
    for i, (r, c) in enumerate(zip(rows, cols, strict=True)):
        x = frame.x_left + (c + 0.5) * frame.resolution
        y = frame.y_top - (r + 0.5) * frame.resolution
        grid.scan(x, y, 0.0, cos_a, sin_a, config.max_range_m, out[i])
    out[out >= config.max_range_m] = np.inf     # no wall within the ray's length
    return out


def blind_curve(distances: np.ndarray, ranges_m=CURVE_RANGES_M) -> np.ndarray:
    """Fraction of sight lines with no wall closer than each range (a wall exactly at r counts
    as seen); 1 for no sight lines at all."""
    flat = np.sort(np.asarray(distances, dtype=float).ravel())
    if flat.size == 0:
        return np.ones(len(ranges_m))
    seen = np.searchsorted(flat, np.asarray(ranges_m, dtype=float), side="right")
    return 1.0 - seen / flat.size


def sightline_features(world, config: SightlineConfig | None = None) -> dict[str, float]:
    """The plan's curve as columns (:func:`curve_columns` → blind fraction), its
    ``sightline_isotropy`` at ``isotropy_range_m``
    (:func:`slam_predict.features.scan_conditioning.mean_isotropy`) and the
    ``floor_elongation`` of the sight lines' floor points
    (:mod:`slam_predict.features.floor_shape`; 1 without points)."""
    config = config or SightlineConfig()
    rows, cols = sample_points(world.occupied, world.resolution, config)
    distances = cast_sight_lines(world, rows, cols, config)
    curve = blind_curve(distances)
    features = {name: float(v) for name, v in zip(curve_columns(), curve, strict=True)}
    features[ISOTROPY_COLUMN] = mean_isotropy(distances, config.isotropy_range_m)
    features[ELONGATION_COLUMN] = (
        elongation(cols * world.resolution, rows * world.resolution, config.spacing_m)
        if rows.size else 1.0)
    return features


def blind_fraction(curve: Mapping[str, float] | np.ndarray, range_m: float) -> float:
    """The blind fraction at ``range_m`` (m) of a curve (its columns, or the values at
    :data:`CURVE_RANGES_M`): log-log interpolation, clamped to the curve's ranges, at least
    :data:`BLIND_FLOOR`."""
    if isinstance(curve, Mapping):
        values = np.array([float(curve[name]) for name in curve_columns()])
    else:
        values = np.asarray(curve, dtype=float)
    logs = np.log(np.maximum(values, BLIND_FLOOR))
    r = min(max(float(range_m), CURVE_RANGES_M[0]), CURVE_RANGES_M[-1])
    return float(np.exp(np.interp(math.log(r), np.log(CURVE_RANGES_M), logs)))
