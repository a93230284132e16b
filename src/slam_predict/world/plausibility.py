"""Is a loaded plan a building at the scale it was given? And is all of it reachable?

:func:`check_scale` refuses (one-line :class:`InputError`, hint at ``--resolution``) a plan
whose free area or extent no building has: free area below :data:`MIN_FREE_M2` (10 m², a
small room) or above :data:`MAX_FREE_M2` (100,000 m², larger than the floors of the largest
office buildings), or free space spanning more than :data:`MAX_EXTENT_M` (2 km) along an
axis. A wrong ``--resolution`` is the usual cause (5 m/px instead of 0.05 m/px makes a 20 m
plan a 2 km building); ``force`` accepts the plan anyway.

:func:`reachability` measures the free space 4-connected to the start cell: a door drawn
closed leaves rooms the robot, and the feature extraction, never enter.
:func:`unreachable_warning` words it when an unreachable free component is at least
:data:`MIN_ROOM_M2` (4 m², a small room): scanned maps hold many small enclosed specks (ipa
Freiburg79: 2.5 % of the free space in pieces ≤ 3.3 m²) that are no rooms, while ipa lab_intel
has a closed 10.6 m² room.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from slam_predict.errors import InputError
from slam_predict.world.model import World

MIN_FREE_M2 = 10.0
MAX_FREE_M2 = 100_000.0
MAX_EXTENT_M = 2_000.0
MIN_ROOM_M2 = 4.0


def free_extent_m(world: World) -> tuple:
    """(width, height) in m of the bounding box of the free cells ((0, 0) when none)."""
    free = ~world.occupied
    if not free.any():
        return 0.0, 0.0
    rows = np.flatnonzero(free.any(axis=1))
    cols = np.flatnonzero(free.any(axis=0))
    return ((cols[-1] - cols[0] + 1) * world.resolution,
            (rows[-1] - rows[0] + 1) * world.resolution)


def free_area_m2(world: World) -> float:
    """Free (non-occupied) area of the plan, m²."""
    return float(np.count_nonzero(~world.occupied)) * world.resolution ** 2


def _scale_problem(area: float, extent: tuple) -> str | None:
    if area < MIN_FREE_M2:
        return f"free area {area:.3g} m² is smaller than any building (< {MIN_FREE_M2:g} m²)"
    if area > MAX_FREE_M2:
        return (f"free area {area:.3g} m² is larger than any building "
                f"(> {MAX_FREE_M2:,.0f} m²)")
    if max(extent) > MAX_EXTENT_M:
        return (f"free space spans {extent[0]:.4g} x {extent[1]:.4g} m, more than any "
                f"building (> {MAX_EXTENT_M:g} m)")
    return None


def check_scale(world: World, force: bool = False) -> None:
    """InputError when the plan's free area or extent is outside what buildings have.

    Args:
        world: the loaded plan.
        force: accept it anyway (the caller's ``--force``).
    """
    problem = _scale_problem(free_area_m2(world), free_extent_m(world))
    if problem is None or force:
        return
    scale = {"stage": "check the floorplan size in the world file",
             "map_server": "check the resolution in the map YAML"}.get(
                 world.provenance.get("format"), "check --resolution")
    raise InputError(f"{problem} at {world.resolution:g} m/px: {scale}, or pass --force to "
                     "use it anyway", world.provenance.get("source"))


@dataclass(frozen=True)
class Reachability:
    """Free space reachable from the start (4-connected) against all free space, m²;
    ``largest_cut_m2``: the largest free component not reachable."""

    reachable_m2: float
    free_m2: float
    largest_cut_m2: float

    @property
    def share(self) -> float:
        """Reachable fraction of the free area (1 when the plan has no free space)."""
        return self.reachable_m2 / self.free_m2 if self.free_m2 > 0 else 1.0


def reachability(world: World) -> Reachability:
    """Area of the free component holding the start cell, and of all free space."""
    free = ~world.occupied
    labels, _ = ndimage.label(free)
    row, col = world.world_to_cell(world.start_pose[:2])
    label = labels[row, col] if world.in_bounds((row, col)) else 0
    sizes = np.bincount(labels.ravel()) * world.resolution ** 2
    sizes[0] = 0.0  # obstacles
    reachable = float(sizes[label]) if label else 0.0
    sizes[label] = 0.0
    return Reachability(reachable, float(sizes.sum()) + reachable, float(sizes.max()))


def unreachable_warning(world: World) -> str | None:
    """A warning when a room-sized part of the free space cannot be reached from the start."""
    reach = reachability(world)
    if reach.largest_cut_m2 < MIN_ROOM_M2:
        return None
    x, y = world.start_pose[:2]
    return (f"only {100 * reach.share:.3g} % of the free space ({reach.reachable_m2:.0f} of "
            f"{reach.free_m2:.0f} m²) is reachable from the start ({x:.2f}, {y:.2f}) m: a "
            "robot starting there never maps the rest (a door drawn closed?); check the plan "
            "or --start")


def free_space(world: World) -> tuple[dict[str, float], list[str]]:
    """A prediction's ``free_space`` entry (m², share) and its unreachable-space warning (none
    or one line)."""
    reach = reachability(world)
    note = unreachable_warning(world)
    return ({"free_m2": reach.free_m2, "reachable_m2": reach.reachable_m2,
             "reachable_share": reach.share}, [note] if note else [])
