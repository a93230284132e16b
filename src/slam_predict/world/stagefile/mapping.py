"""Map a parsed Stage world file onto a :class:`World`.

Rules:
- **Floor plan**: the model with a ``bitmap`` and the largest ``size`` area. Its image is read
  by the threshold rule of :mod:`slam_predict.world.bitmap` (not Stage's ≤ 127 rule) and
  stretched to ``size`` [W H]: a pixel spans W/cols × H/rows m. When those differ (a ``size``
  that stretches the image unevenly) the bitmap is resampled onto square pixels at the finer of
  the two (resolution = min(W/cols, H/rows)), so no wall gets thinner than a pixel. The bitmap
  centre is the model's global pose (+ its ``origin`` offset); a floor plan turned by a multiple
  of 90° is rotated onto the grid (other angles are refused).
  Free space touching the image border is outside the building even when the model sets
  ``boundary 1`` (Stage would close it with 1 cm walls): one rule for every bitmap.
- **Other obstacles**: further bitmap models and plain ``model`` boxes (a model without bitmap
  fills its ``size`` rectangle, Stage's default block; ``block`` children give polygons) are
  drawn into the grid (cells whose centre is inside, :mod:`slam_predict.world.raster`) when
  they have ``obstacle_return`` ≠ 0 and are not part of a robot.
- **Robot**: the first ``position`` model: its global pose is the start pose (``start_given``);
  ``size`` → footprint side (the larger of x, y), ``velocity_bounds`` / ``acceleration_bounds``
  (x max and angular max), ``odom_error``, ``localization``, ``drive``. Missing properties take
  Stage's defaults where Stage has a fixed one (localization "gps", velocity ±1 m/s, ±90 °/s) and
  slam_predict's RobotSpec defaults otherwise (odom_error: Stage draws it at random per run).
- **Laser**: the first ``sensor`` of the first ``ranger`` on the robot; pose on the robot =
  ranger pose ⊕ sensor pose; Stage's sensor defaults (range [0 5], fov 0.1°, 1 sample) apply
  to missing properties; ``noise [c p a]`` → noise_std = √c (c is the variance in m²), p and a
  are not modelled. ``update_interval`` (ms) of the ranger gives the rate. No ranger → LaserSpec
  defaults.
- **World**: ``interval_sim`` ms → s. Stage's ``resolution`` (raytrace cell), ``speedup``,
  ``quit_time`` and ``threads`` are kept in ``provenance["stage"]``.
"""
from __future__ import annotations

import logging
import math
import os

import numpy as np

from slam_predict.errors import InputError
from slam_predict.geometry import compose, inverse, transform_points
from slam_predict.world import bitmap
from slam_predict.world.model import LaserSpec, RobotSpec, World, check_occupancy
from slam_predict.world.raster import Grid, fill_polygons
from slam_predict.world.stagefile.parser import Entity
from slam_predict.world.stagefile.values import Units, read_tuple, read_value

LOG = logging.getLogger(__name__)


def _where(entity: Entity, name: str | None = None) -> tuple[str, int | None]:
    token = entity.props[name].token if name and name in entity.props else entity.token
    return (token.path, token.line) if token is not None else (None, None)


def _pose(entity: Entity, units: Units) -> np.ndarray:
    """Local pose (x, y, yaw) of an entity: ``pose`` ⊕ ``origin`` offsets are kept apart."""
    x, y, _, a = read_tuple(entity, "pose", "llla", units, (0.0, 0.0, 0.0, 0.0))
    return np.array([x, y, a])


def global_poses(root: Entity, units: Units) -> dict[int, np.ndarray]:
    """Global pose of every entity (keyed by id()); children are relative to their parent."""
    poses = {id(root): np.zeros(3)}
    for entity, parent in root.walk():
        if parent is root:  # top level: the pose as written (yaw normalised like Stage)
            poses[id(entity)] = _normalised(_pose(entity, units))
        elif parent is not None:
            poses[id(entity)] = compose(poses[id(parent)], _pose(entity, units))
    return poses


def _normalised(pose: np.ndarray) -> np.ndarray:
    """Yaw brought into [-π, π] by whole turns, leaving in-range angles bit-exact (Stage)."""
    while pose[2] > math.pi:
        pose[2] -= 2 * math.pi
    while pose[2] < -math.pi:
        pose[2] += 2 * math.pi
    return pose


def _size(entity: Entity, units: Units, required: bool) -> tuple[float, float] | None:
    prop = entity.props.get("size")
    if prop is None:
        if required:
            raise InputError(f"{entity.label} with a bitmap has no 'size [W H Z]'",
                             *_where(entity))
        return None
    if len(prop.values) == 2:
        LOG.warning("%s:%d: size has 2 values; Stage 4 needs [W H Z]", prop.token.path,
                    prop.token.line)
        w, h = read_tuple(entity, "size", "ll", units)
    else:
        w, h, _ = read_tuple(entity, "size", "lll", units)
    if not (w > 0 and h > 0):
        raise InputError(f"size of {entity.label} must be > 0, got [{w:g} {h:g}]",
                         *_where(entity, "size"))
    return w, h


def _bitmap_path(entity: Entity, top_path: str) -> str:
    prop = entity.props["bitmap"]
    name = os.path.expanduser(prop.values[0].text) if prop.values else ""
    if not name:
        raise InputError("bitmap name is empty", prop.token.path, prop.token.line)
    if os.path.isabs(name):
        return name
    # Beside the file that names it; else beside the top-level world file (Stage's rule).
    beside = os.path.join(os.path.dirname(prop.token.path), name)
    fallback = os.path.join(os.path.dirname(top_path), name)
    return beside if os.path.isfile(beside) or not os.path.isfile(fallback) else fallback


def _read_bitmap(entity: Entity, free_threshold: int, top_path: str,
                 floorplan: bool = True) -> tuple[np.ndarray, str]:
    """Occupancy of an entity's bitmap; only the floor plan loses its border-connected space."""
    path = _bitmap_path(entity, top_path)
    if not os.path.isfile(path):
        prop = entity.props["bitmap"]
        raise InputError(f"bitmap '{prop.values[0].text}' not found (looked for {path})",
                         prop.token.path, prop.token.line)
    if floorplan:
        return bitmap.load_occupancy(path, free_threshold), path
    return ~bitmap.free_mask(bitmap.read_grey(path), free_threshold), path


def _under_robot(root: Entity) -> set:
    """ids of entities that belong to a position model (robots are not static obstacles)."""
    inside = set()
    for entity, parent in root.walk():
        if entity.type == "position" or (parent is not None and id(parent) in inside):
            inside.add(id(entity))
    return inside


def _floorplan_candidates(root: Entity, robot_parts: set) -> list[Entity]:
    return [e for e, _ in root.walk() if "bitmap" in e.props and id(e) not in robot_parts]


def _stretch(occupied: np.ndarray, size: tuple[float, float]) -> tuple[np.ndarray, float, bool]:
    """Square-pixel occupancy of a bitmap stretched to ``size`` m, its m/px, resampled?"""
    rows, cols = occupied.shape
    res_x, res_y = size[0] / cols, size[1] / rows
    if abs(res_x - res_y) <= 1e-9 * max(res_x, res_y):
        return occupied, res_x, False
    resolution = min(res_x, res_y)
    LOG.warning("size %.3f x %.3f m stretches the %d x %d px bitmap unevenly (%.4f x %.4f m/px);"
                " resampled to square %.4f m pixels", size[0], size[1], cols, rows, res_x,
                res_y, resolution)
    return bitmap.resample_square(occupied, size, resolution), resolution, True


def _quarter_turns(yaw: float, main: Entity) -> int:
    """Number of 90° counter-clockwise turns of a floor plan with ``yaw`` rad (else refused)."""
    turns = yaw / (math.pi / 2)
    if abs(turns - round(turns)) > 1e-9:
        raise InputError(f"floor plan rotated by {math.degrees(yaw):.3f} deg: only multiples "
                         "of 90 deg are supported", *_where(main, "pose"))
    return int(round(turns)) % 4


def _model_polygons(entity: Entity, units: Units, size) -> list[np.ndarray]:
    """Footprint polygons of a bitmap-less model in its local frame (m)."""
    blocks = [c for c in entity.children if c.type == "block"]
    if not blocks:
        w, h = size
        return [np.array([[-w / 2, -h / 2], [w / 2, -h / 2], [w / 2, h / 2], [-w / 2, h / 2]])]
    polys = []
    for block in blocks:
        count = read_value(block, "points", "i", units, 0)
        pts = [read_tuple(block, f"point[{k}]", "ll", units) for k in range(count)]
        if any(p is None for p in pts) or count < 3:
            raise InputError(f"block needs 'points N' and point[0..N-1], got {count} points",
                             *_where(block))
        polys.append(np.array(pts, dtype=float))
    # Stage scales the blocks' bounding box to the model size, centred on the model.
    allpts = np.vstack(polys)
    lo, hi = allpts.min(axis=0), allpts.max(axis=0)
    span = np.where(hi - lo > 0, hi - lo, 1.0)
    return [((p - lo) / span - 0.5) * np.asarray(size) for p in polys]


def _draw_obstacles(world: World, root: Entity, main: Entity, poses, units: Units,
                    robot_parts: set, free_threshold: int, top_path: str) -> np.ndarray:
    occupied = world.occupied.copy()
    rows, cols = occupied.shape
    grid = Grid(rows, cols, world.resolution, tuple(world.origin))
    for entity, _ in root.walk():
        if entity is main or id(entity) in robot_parts or entity.type != "model":
            continue
        if read_value(entity, "obstacle_return", "f", units, 1) == 0:
            continue
        size = _size(entity, units, required="bitmap" in entity.props)
        if size is None:
            size = (0.1, 0.1)
        pose = poses[id(entity)]
        if "bitmap" in entity.props:
            sub, _ = _read_bitmap(entity, free_threshold, top_path, floorplan=False)
            centres = world.cell_to_world(np.stack(np.indices((rows, cols)), axis=-1))
            local = transform_points(inverse(pose), centres.reshape(-1, 2)).reshape(rows, cols, 2)
            sr, sc = sub.shape
            c = np.floor((local[..., 0] / size[0] + 0.5) * sc).astype(int)
            r = np.floor((0.5 - local[..., 1] / size[1]) * sr).astype(int)
            inside = (c >= 0) & (c < sc) & (r >= 0) & (r < sr)
            occupied[inside] |= sub[r[inside], c[inside]]
            continue
        polygons = [transform_points(pose, poly) for poly in _model_polygons(entity, units, size)]
        fill_polygons(occupied, grid, polygons, True)
    return occupied


def _robot_spec(robot: Entity, units: Units) -> tuple[RobotSpec, list[str]]:
    spec, defaults = RobotSpec(), []
    size = _size(robot, units, required=False)
    if size is None:
        defaults.append("size")
    side = max(size) if size else spec.footprint_side
    vel = read_tuple(robot, "velocity_bounds", "llllllaa", units,
                     (-1, 1, -1, 1, -1, 1, -math.pi / 2, math.pi / 2))
    acc = read_tuple(robot, "acceleration_bounds", "llllllaa", units)
    if acc is None:
        defaults.append("acceleration_bounds")
        acc = (0, spec.max_acc_x, 0, 0, 0, 0, 0, spec.max_acc_theta)
    odom = read_tuple(robot, "odom_error", "llla", units)
    if odom is None:
        defaults.append("odom_error")
        odom = spec.odom_error
    localization = read_value(robot, "localization", "s", units, "gps")
    drive = read_value(robot, "drive", "s", units, "diff")
    for name, value, choices in (("localization", localization, ("gps", "odom")),
                                 ("drive", drive, ("diff", "omni", "car"))):
        if value not in choices:
            raise InputError(f"{name} \"{value}\" is not one of {list(choices)}",
                             *_where(robot, name))
    return RobotSpec(footprint_side=side, max_vel_x=vel[1], max_vel_theta=vel[7],
                     max_acc_x=acc[1], max_acc_theta=acc[7], odom_error=tuple(odom),
                     localization=localization, drive=drive), defaults


def _laser_spec(robot: Entity, units: Units) -> tuple[LaserSpec, list[str]]:
    for ranger in (c for c in robot.children if c.type == "ranger"):
        sensors = [c for c in ranger.children if c.type == "sensor"]
        if not sensors:
            continue
        sensor = sensors[0]
        rmin, rmax = read_tuple(sensor, "range", "ll", units, (0.0, 5.0))
        fov = read_value(sensor, "fov", "a", units, 0.1 * units.angle)
        samples = read_value(sensor, "samples", "i", units, 1)
        noise = read_tuple(sensor, "noise", "lla", units, (0.0, 0.0, 0.0))
        interval_ms = read_value(ranger, "update_interval", "f", units, 100.0)
        if samples < 1 or not fov > 0 or not rmax > rmin or interval_ms <= 0:
            raise InputError("ranger sensor needs samples ≥ 1, fov > 0, range max > min and "
                             "update_interval > 0", *_where(sensor))
        if noise[1] or noise[2]:
            LOG.warning("ranger noise: proportional and angular parts are not modelled")
        pose = compose(_pose(ranger, units), _pose(sensor, units))
        return LaserSpec(fov=fov, samples=samples, range_min=rmin, range_max=rmax,
                         rate_hz=1000.0 / interval_ms, pose=tuple(float(v) for v in pose),
                         noise_std=math.sqrt(max(noise[0], 0.0))), []
    return LaserSpec(), ["laser"]


def _stage_props(root: Entity, units: Units) -> dict:
    return {
        "interval_sim_ms": read_value(root, "interval_sim", "f", units, 100.0),
        "resolution": read_value(root, "resolution", "f", units, 0.02),
        "speedup": read_value(root, "speedup", "f", units, 1.0),
        "quit_time": read_value(root, "quit_time", "f", units, 0.0),
        "threads": read_value(root, "threads", "i", units, 1),
    }


def to_world(root: Entity, units: Units, path: str,
             free_threshold: int = bitmap.FREE_THRESHOLD) -> World:
    """The World described by the parsed world file ``root`` (read from ``path``)."""
    stage = _stage_props(root, units)
    if not stage["interval_sim_ms"] > 0:
        raise InputError("interval_sim must be > 0 ms", *_where(root, "interval_sim"))
    robot_parts = _under_robot(root)
    candidates = _floorplan_candidates(root, robot_parts)
    if not candidates:
        raise InputError("no floor plan: no model has a 'bitmap'", path)
    sizes = [_size(e, units, required=True) for e in candidates]
    main = candidates[int(np.argmax([w * h for w, h in sizes]))]
    size = sizes[candidates.index(main)]
    poses = global_poses(root, units)
    offset = read_tuple(main, "origin", "llla", units, (0.0, 0.0, 0.0, 0.0))
    centre = compose(poses[id(main)], [offset[0], offset[1], offset[3]])
    quarter_turns = _quarter_turns(centre[2], main)
    occupied, bitmap_path = _read_bitmap(main, free_threshold, path)
    bitmap_px = [int(occupied.shape[1]), int(occupied.shape[0])]
    occupied, resolution, resampled = _stretch(occupied, size)
    occupied = np.rot90(occupied, quarter_turns)   # counter-clockwise, as yaw
    name = os.path.splitext(os.path.basename(path))[0]
    world = World(name=name, occupied=occupied, resolution=resolution,
                  origin=(float(centre[0]), float(centre[1])),
                  interval_sim=stage["interval_sim_ms"] / 1000.0)
    world = world.replace(occupied=_draw_obstacles(world, root, main, poses, units,
                                                   robot_parts, free_threshold, path))
    check_occupancy(world.occupied, path)
    robots = [e for e, _ in root.walk() if e.type == "position"]
    provenance = {"source": os.path.abspath(path), "format": "stage", "size_m": list(size),
                  "floorplan_quarter_turns": quarter_turns,
                  "bitmap": bitmap_path, "bitmap_px": bitmap_px, "resampled": resampled,
                  "start_given": bool(robots), "stage": stage}
    if not robots:
        provenance["defaults"] = ["robot", "laser"]
        return world.replace(provenance=provenance)
    if len(robots) > 1:
        LOG.warning("%s: %d position models; the first one is the robot", path, len(robots))
    robot_spec, robot_defaults = _robot_spec(robots[0], units)
    laser_spec, laser_defaults = _laser_spec(robots[0], units)
    provenance["defaults"] = robot_defaults + laser_defaults
    return world.replace(start_pose=poses[id(robots[0])], robot=robot_spec, laser=laser_spec,
                         provenance=provenance)
