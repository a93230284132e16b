"""``load_plan``: one entry point from any floor-plan file to a World with a valid start pose.

Formats, chosen by the file name's extension:

- ``.world`` — a Stage 4 world file (:mod:`slam_predict.world.stagefile`); its floorplan
  ``size`` sets the scale, so ``resolution`` must not be given.
- ``.png .pgm .ppm .pnm .bmp .tif .tiff .jpg .jpeg`` — a bitmap floor plan read by the
  threshold rule of :mod:`slam_predict.world.bitmap`. Resolution: the ``resolution`` argument,
  else the ``resolution`` of a map_server YAML beside the image (same stem, ``.yaml``/``.yml``),
  else an error naming ``--resolution``.
- ``.yaml .yml`` — a map_server map description (``image``, ``resolution``, ``origin``,
  ``negate``, ``occupied_thresh``, ``free_thresh``; read by :mod:`slam_predict.formats.mapserver`).
  Its own rule decides what is free: p = (255 − grey)/255 (grey/255 when ``negate``); a pixel
  is free iff p < free_thresh; occupied and unknown pixels are obstacles.
- ``.xml`` — a layout XML (:func:`slam_predict.world.layout.load_layout`).

Frames. A plain image is centred on the world origin (Stage's convention: ``World.origin`` =
(0, 0)). A map_server ``origin [ox oy yaw]`` is the map-frame pose of the image's lower-left
corner, so ``World.origin`` = (ox + W/2, oy + H/2) with W, H the image size in m: the World's
frame *is* the ROS map frame (poses read in RViz can be passed to ``--start``), and a Stage world
written from it puts the floorplan at that pose. A non-zero yaw is ignored with a warning (as
most of the ROS navigation stack does).

In every case free space connected to the image border is outside the building, and the start
pose follows :func:`slam_predict.world.start.resolve_start`.
"""
from __future__ import annotations

import importlib
import logging
import math
import os
from collections.abc import Sequence

import numpy as np

from slam_predict.errors import InputError, require_file
from slam_predict.world import bitmap
from slam_predict.world.model import World
from slam_predict.world.start import resolve_start

LOG = logging.getLogger(__name__)
IMAGE_SUFFIXES = (".png", ".pgm", ".ppm", ".pnm", ".bmp", ".tif", ".tiff", ".jpg", ".jpeg")
YAML_SUFFIXES = (".yaml", ".yml")
PLAN_SUFFIXES = (".world",) + IMAGE_SUFFIXES + YAML_SUFFIXES + (".xml",)


def _check_resolution(resolution: float | None, source: str, what: str = "--resolution"):
    if resolution is None:
        return None
    try:
        value = float(resolution)
    except (TypeError, ValueError):
        raise InputError(f"{what} must be a number of m/px, got {resolution!r}", source) from None
    if not (value > 0 and math.isfinite(value)):
        raise InputError(f"{what} must be > 0 m/px, got {resolution}", source)
    return value


def _read_map_yaml(path: str):
    """The map_server map of a YAML (formats.mapserver), with its resolution checked."""
    from slam_predict.formats.mapserver import read_map

    meta = read_map(path)
    _check_resolution(meta.resolution, path, "resolution")
    return meta


def _centre_from_origin(origin, shape, resolution: float, source: str):
    """World xy of the bitmap centre from a map_server origin (pose of the lower-left corner)."""
    ox, oy, yaw = (float(v) for v in origin)
    if abs(yaw) > 1e-12:
        LOG.warning("%s: origin yaw %.3f rad ignored", source, yaw)
    rows, cols = shape
    return ox + cols * resolution / 2.0, oy + rows * resolution / 2.0


def _load_map_yaml(path: str) -> World:
    meta = _read_map_yaml(path)
    free = np.flipud(meta.to_occupancy() == 0)   # map_server's trinary rule; unknown = obstacle
    free = bitmap.remove_outside(free, path)
    res = meta.resolution
    return World(name=os.path.splitext(os.path.basename(path))[0], occupied=~free,
                 resolution=res, origin=_centre_from_origin(meta.origin, free.shape, res, path),
                 provenance={"source": os.path.abspath(path), "format": "map_server",
                             "map_origin": list(meta.origin), "start_given": False})


def _yaml_beside(image: str) -> str | None:
    stem = os.path.splitext(image)[0]
    for suffix in YAML_SUFFIXES:
        if os.path.isfile(stem + suffix):
            return stem + suffix
    return None


def _load_image(path: str, resolution: float | None, free_threshold: int) -> World:
    origin, provenance = (0.0, 0.0), {"source": os.path.abspath(path), "format": "image"}
    occupied = bitmap.load_occupancy(path, free_threshold)
    yaml_path = _yaml_beside(path)
    if yaml_path is not None:
        meta = _read_map_yaml(yaml_path)
        if resolution is None:
            resolution = meta.resolution
            provenance["resolution_from"] = yaml_path
        origin = _centre_from_origin(meta.origin, occupied.shape, resolution, yaml_path)
        provenance["map_origin"] = list(meta.origin)
    if resolution is None:
        raise InputError("image has no scale: give --resolution M_PER_PX (or put a map_server "
                         "YAML with the same name beside it)", path)
    provenance.update(start_given=False, free_threshold=free_threshold)
    return World(name=os.path.splitext(os.path.basename(path))[0], occupied=occupied,
                 resolution=resolution, origin=origin, provenance=provenance)


def _load_layout(path: str, resolution, start, snap_start, layout_options) -> World:
    try:
        layout = importlib.import_module("slam_predict.world.layout")
    except ModuleNotFoundError as exc:
        if exc.name == "slam_predict.world.layout":
            raise InputError("layout XML support is not installed", path) from None
        raise
    kwargs = {k: v for k, v in layout_options.items() if v is not None}
    if resolution is not None:
        kwargs["resolution"] = resolution
    return layout.load_layout(path, start=start, snap_start=snap_start, **kwargs)


def load_plan(path: os.PathLike | str, resolution: float | None = None,
              start: Sequence[float] | None = None, snap_start: bool = False,
              free_threshold: int = bitmap.FREE_THRESHOLD, *,
              wall_thickness: float | None = None,
              door_width: float | None = None) -> World:
    """Load a floor plan (.world, image, map_server YAML or layout XML) as a World.

    Args:
        path: the plan file (format from its extension, see the module docstring).
        resolution: m/px for images (and layout XML); not allowed with a .world.
        start: (x, y[, yaw]) in m, m, deg in the World frame; default: the world file's robot
            pose, else the start-pose rule of :mod:`slam_predict.world.start`.
        snap_start: move a start pose in a wall to the nearest free cell instead of failing.
        free_threshold: grey level (0–255) from which an image pixel is free.
        wall_thickness, door_width: layout XML options (m); None = the layout's defaults.
    Raises:
        InputError: for every bad input (missing/corrupt file, no enclosed free space, bad
        scale, start pose in a wall or outside the map, ...).
    """
    path = require_file(path, "plan")
    suffix = os.path.splitext(path)[1].lower()
    resolution = _check_resolution(resolution, path)
    if not 0 < int(free_threshold) <= 255:
        raise InputError(f"free threshold must be in 1..255, got {free_threshold}", path)
    if suffix == ".xml":
        return _load_layout(path, resolution, start, snap_start,
                            {"wall_thickness": wall_thickness, "door_width": door_width})
    if suffix == ".world":
        if resolution is not None:
            raise InputError("--resolution does not apply to a .world file (its floorplan "
                             "size sets the scale)", path)
        from slam_predict.world.stagefile import read_world

        world = read_world(path, free_threshold)
    elif suffix in YAML_SUFFIXES:
        if resolution is not None:
            raise InputError("--resolution does not apply to a map YAML (it sets its own)", path)
        world = _load_map_yaml(path)
    elif suffix in IMAGE_SUFFIXES:
        world = _load_image(path, resolution, int(free_threshold))
    else:
        raise InputError(f"unknown plan format '{suffix or '(none)'}' (expected one of "
                         f"{', '.join(PLAN_SUFFIXES)})", path)
    return resolve_start(world, start, snap_start)
