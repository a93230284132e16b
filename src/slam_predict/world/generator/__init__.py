"""Procedural office and school buildings as Worlds with ground-truth rooms and doors.

``generate(kind, area_m2, seed)`` draws a building from ``numpy.random.default_rng(seed)``
(same seed, same building): a corridor spine (straight, L, T, U, ring around an optional inner
courtyard, or comb; :mod:`.spine`), room bands on both sides cut into rooms of varied widths,
small rooms and halls (:mod:`.plan`), doors 0.8–1.5 m wide and full-width corridor passages
(:mod:`.doors`), walls 0.1–0.2 m inside and 0.2–0.3 m outside, rasterised at ``resolution``
m/px (:mod:`.build`). The requested area is the **free floor area** of the result (free cells ×
resolution²); the corridor length is fitted to it. The start pose is the point of largest
clearance in the largest corridor, facing along it.

Ground truth on the World: ``rooms`` (every space, corridors included, one polygon each) and
``doors`` (door openings, and for passages between corridor pieces the whole shared wall), so
that closing every door splits the free space into exactly one region per room.
"""
from __future__ import annotations

import math

import numpy as np

from slam_predict.errors import InputError
from slam_predict.world.generator.params import KINDS, sample_params
from slam_predict.world.model import World

GENERATOR_VERSION = "1.0"
MIN_AREA_M2 = 50.0
MAX_AREA_M2 = 50000.0

__all__ = ["generate", "metadata", "KINDS", "GENERATOR_VERSION"]


def _check(kind: str, area_m2: float, seed: int, resolution: float) -> None:
    from slam_predict.errors import did_you_mean

    if kind not in KINDS:
        raise InputError(f"unknown building kind '{kind}' (one of {', '.join(KINDS)})"
                         + did_you_mean(kind, KINDS))
    if not (math.isfinite(area_m2) and MIN_AREA_M2 <= area_m2 <= MAX_AREA_M2):
        raise InputError(f"area must be between {MIN_AREA_M2:g} and {MAX_AREA_M2:g} m² "
                         f"(got {area_m2:g})")
    if not (math.isfinite(resolution) and 0.01 <= resolution <= 0.5):
        raise InputError(f"resolution must be between 0.01 and 0.5 m/px (got {resolution:g})")
    if int(seed) < 0:
        raise InputError(f"seed must be ≥ 0 (got {seed})")


def generate(kind: str, area_m2: float, seed: int, resolution: float = 0.05,
             name: str | None = None) -> World:
    """A generated ``kind`` ('office' or 'school') building of about ``area_m2`` m² free area.

    Deterministic from ``seed``. The metadata (kind, areas, seed, shape, parameters, version)
    is in ``world.provenance['generator']``; :func:`metadata` gives the JSON-ready record.
    """
    from slam_predict.world.generator.build import corridor_start, fit_plan, rasterise_plan

    _check(kind, area_m2, seed, resolution)
    rng = np.random.default_rng(int(seed))
    params = sample_params(kind, area_m2, rng)
    layout_seed = int(rng.integers(2 ** 62))
    plan = fit_plan(params, area_m2, layout_seed)
    free, grid, rooms, doors, closed, owner = rasterise_plan(plan, resolution)
    actual = float(free.sum()) * resolution ** 2
    if abs(actual - area_m2) > 0.06 * area_m2:  # the raster disagrees with the estimate
        plan = fit_plan(params, area_m2 * area_m2 / actual, layout_seed)
        free, grid, rooms, doors, closed, owner = rasterise_plan(plan, resolution)
        actual = float(free.sum()) * resolution ** 2
    start = corridor_start(plan, free, owner, grid)
    info = {"version": GENERATOR_VERSION, "kind": kind, "seed": int(seed),
            "area_requested_m2": float(area_m2), "area_m2": round(actual, 2),
            "shape": plan.shape, "corridor_length_m": round(plan.length, 2),
            "params": plan.params.to_dict(), "closed_m2": round(closed, 3),
            "room_categories": [s.category for s in plan.spaces],
            "passages": [d.passage for d in plan.doors]}
    return World(name=name or f"{kind}_{int(round(area_m2))}_s{int(seed)}", occupied=~free,
                 resolution=resolution, start_pose=start, origin=grid.origin, rooms=rooms,
                 doors=doors, provenance={"source": "generator", "format": "generated",
                                          "start_given": True, "generator": info})


def metadata(world: World) -> dict:
    """The JSON record of a generated world: generator info, start pose, rooms (with their
    category) and doors (``kind`` 'door' or 'passage'), in the World frame (m)."""
    from slam_predict.world.groundtruth import doors_record, rooms_record

    info = dict(world.provenance.get("generator", {}))
    categories = info.pop("room_categories", [""] * len(world.rooms))
    passages = info.pop("passages", [False] * len(world.doors))
    rooms = [{**r, "category": c}
             for r, c in zip(rooms_record(world.rooms), categories, strict=False)]
    doors = [{**d, "kind": "passage" if p else "door"}
             for d, p in zip(doors_record(world.doors), passages, strict=False)]
    x, y, yaw = (float(v) for v in world.start_pose)
    return {**info, "name": world.name, "resolution": world.resolution,
            "size_m": [round(v, 4) for v in world.size_m],
            "start_pose": [round(x, 4), round(y, 4), round(math.degrees(yaw), 4)],
            "start_pose_units": "m, m, deg", "rooms": rooms, "doors": doors}
