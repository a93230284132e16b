"""Write a World as a Stage 4 world file plus a clean 0/255 PNG bitmap beside it.

The bitmap has only two values, 0 (obstacle or outside) and 255 (free), so Stage's own rule
(first channel ≤ 127 → obstacle) and ours (grey ≥ 250 → free) read it alike. The world
file defines ``floorplan`` (a model with the bitmap, stretched to ``size`` = bitmap pixels ×
resolution and centred on the World's origin), a ``ranger`` with one ``sensor`` from the
LaserSpec, and a ``position`` robot from the RobotSpec at the World's start pose. Angles are
written in degrees, numbers in plain decimals (Stage cannot read exponents). Both files are
written atomically (PNG first, so the world never names a missing bitmap).

Rooms and doors are not part of a Stage world; writers that need them store them separately.
"""
from __future__ import annotations

import logging
import math
import os
from pathlib import Path

import cv2
import numpy as np

from slam_predict import __version__
from slam_predict.atomic import write_bytes, write_text
from slam_predict.world.model import World

LOG = logging.getLogger(__name__)
STAGE_RESOLUTION = 0.025  # m per Stage raytrace cell (Stage's default is 0.02)


def fmt(value: float) -> str:
    """A float in the shortest plain decimal form that reads back exactly (no exponent)."""
    text = np.format_float_positional(float(value), trim="-")
    return "0" if text in ("-0", "0") else text


def deg(angle_rad: float) -> str:
    """An angle in rad written in degrees (Stage's default unit_angle)."""
    return fmt(math.degrees(angle_rad))


def bitmap_png(world: World) -> bytes:
    """The World's occupancy as PNG bytes: 0 = obstacle/outside, 255 = free."""
    grey = np.where(world.occupied, 0, 255).astype(np.uint8)
    ok, data = cv2.imencode(".png", grey)
    if not ok:  # pragma: no cover - OpenCV always encodes uint8 grey
        raise RuntimeError("PNG encoding failed")
    return data.tobytes()


def _quote(text: str) -> str:
    """Text safe inside a Stage string (no quotes or line breaks; Stage has no escapes)."""
    return str(text).replace('"', "'").replace("\n", " ").replace("\r", " ")[:200]


def _tuple(*values: str) -> str:
    return "[ " + " ".join(values) + " ]"


def _update_interval_ms(rate_hz: float) -> int:
    ms = 1000.0 / rate_hz
    if abs(ms - round(ms)) > 1e-9:
        LOG.warning("laser rate %.3f Hz written as update_interval %d ms (Stage reads an integer)",
                    rate_hz, round(ms))
    return max(1, int(round(ms)))


def world_text(world: World, bitmap_name: str) -> str:
    """The text of the Stage world file for ``world`` whose bitmap file is ``bitmap_name``."""
    width, height = world.size_m
    robot, laser = world.robot, world.laser
    x, y, yaw = (float(v) for v in world.start_pose)
    ex, ey, ez, ea = robot.odom_error
    source = str(world.provenance.get("source", "")).replace("\n", " ")
    stage_res = min(STAGE_RESOLUTION, world.resolution)
    side = fmt(robot.footprint_side)
    noise = ""
    if laser.noise_std > 0:
        noise = f"\n    noise {_tuple(fmt(laser.noise_std ** 2), '0', '0')}"
    window_scale = fmt(round(760.0 / max(width, height), 3))
    lines = f"""\
# Stage 4 world "{_quote(world.name)}" written by slam_predict {__version__}.
# Source: {source or "(generated)"}
# Bitmap {bitmap_name}: {world.shape[1]} x {world.shape[0]} px at {fmt(world.resolution)} m/px,
# 0 = obstacle, 255 = free. Angles in degrees, lengths in metres.

define floorplan model
(
  color "gray30"
  boundary 1
  gui_nose 0
  gui_grid 0
  gui_move 0
  gui_outline 0
  gripper_return 0
  fiducial_return 0
  ranger_return 1
  obstacle_return 1
)

define slam_predict_laser ranger
(
  sensor
  (
    range {_tuple(fmt(laser.range_min), fmt(laser.range_max))}
    fov {deg(laser.fov)}
    samples {int(laser.samples)}{noise}
  )
  update_interval {_update_interval_ms(laser.rate_hz)}
  color "black"
  size [ 0.05 0.05 0.1 ]
)

# acceleration_bounds only matter in Stage's acceleration mode (stage_ros uses velocity mode);
# an angular bound of 0 means "unlimited" to slam_predict.
define slam_predict_robot position
(
  size {_tuple(side, side, '0.25')}
  drive "{robot.drive}"
  localization "{robot.localization}"
  odom_error {_tuple(fmt(ex), fmt(ey), fmt(ez), deg(ea))}
  velocity_bounds {_tuple(fmt(-robot.max_vel_x), fmt(robot.max_vel_x), '-1', '1', '-1', '1',
                          deg(-robot.max_vel_theta), deg(robot.max_vel_theta))}
  acceleration_bounds {_tuple(fmt(-robot.max_acc_x), fmt(robot.max_acc_x), '-1', '1', '-1', '1',
                              deg(-robot.max_acc_theta), deg(robot.max_acc_theta))}
  gui_nose 1
  slam_predict_laser( pose {_tuple(fmt(laser.pose[0]), fmt(laser.pose[1]), '0',
                                   deg(laser.pose[2]))} )
)

interval_sim {fmt(world.interval_sim * 1000.0)}
resolution {fmt(stage_res)}
threads 1

window
(
  size [ 800 800 ]
  scale {window_scale}
  center {_tuple(fmt(world.origin[0]), fmt(world.origin[1]))}
  rotate [ 0 0 ]
  show_data 1
)

floorplan
(
  name "{_quote(world.name)}"
  bitmap "{_quote(bitmap_name)}"
  size {_tuple(fmt(width), fmt(height), '1')}
  pose {_tuple(fmt(world.origin[0]), fmt(world.origin[1]), '0', '0')}
)

slam_predict_robot
(
  name "robot"
  pose {_tuple(fmt(x), fmt(y), '0', deg(yaw))}
  color "red"
)
"""
    return lines


def write_world(world: World, path: os.PathLike | str) -> Path:
    """Write ``world`` as ``path`` (a .world file) and its PNG bitmap beside it.

    The bitmap is ``<stem>.png`` in the same folder. Returns the world file's path.
    """
    path = Path(path)
    if path.suffix != ".world":
        path = path.with_name(path.name + ".world")
    png = path.with_suffix(".png")
    path.parent.mkdir(parents=True, exist_ok=True)
    write_bytes(png, bitmap_png(world))
    write_text(path, world_text(world, png.name))
    LOG.info("wrote %s and %s", path, png.name)
    return path
