"""What a Stage 4 world file may contain: entity types and the properties each one reads.

Names follow Stage 4.1–4.3 (libstage model.cc, model_position.cc, model_ranger.cc, world.cc,
worldgui.cc). Properties are checked strictly for the world, ``model``, ``position``, ``ranger``,
its ``sensor`` blocks and ``block``; the contents of ``window`` (GUI only) are ignored. Stage
types we do not simulate (camera, fiducial, ...) are accepted with any property, since they do
not change the World.
"""
from __future__ import annotations

import re

# Entity types Stage 4 knows (typetable.cc) plus the sub-blocks that are not models.
MODEL_TYPES = frozenset({
    "model", "position", "ranger", "camera", "fiducial", "blobfinder", "bumper", "gripper",
    "actuator", "blinkenlight", "lightindicator"})
SUB_BLOCKS = frozenset({"sensor", "block"})
GUI_TYPES = frozenset({"window"})
BUILTIN_TYPES = MODEL_TYPES | SUB_BLOCKS | GUI_TYPES
# Types whose properties we do not check (they do not affect the World).
LOOSE_TYPES = frozenset({"camera", "fiducial", "blobfinder", "bumper", "gripper", "actuator",
                         "blinkenlight", "lightindicator"})

WORLD_PROPS = frozenset({
    "name", "interval_sim", "interval_real", "resolution", "speedup", "quit_time", "threads",
    "show_clock", "show_clock_interval", "paused", "unit_length", "unit_angle", "test"})

MODEL_PROPS = frozenset({
    "name", "pose", "origin", "size", "color", "color_rgba", "bitmap", "boundary", "mass",
    "map_resolution", "fiducial_return", "fiducial_key", "obstacle_return", "ranger_return",
    "blob_return", "gripper_return", "laser_return", "gravity_return", "sticky_return",
    "gui_nose", "gui_grid", "gui_outline", "gui_move", "gui_movemask", "update_interval",
    "stack_children", "ctrl", "say", "alwayson", "watts", "watts_give", "watts_take", "joules",
    "joules_capacity", "kjoules", "kjoules_capacity", "friction", "trail_length",
    "trail_interval", "debug", "blocks", "velocity", "log_state"})

POSITION_PROPS = MODEL_PROPS | frozenset({
    "drive", "localization", "localization_origin", "odom_error", "wheelbase",
    "velocity_bounds", "acceleration_bounds", "velocity_enable"})

SENSOR_PROPS = frozenset({"pose", "size", "range", "fov", "samples", "noise", "color",
                          "color_rgba"})
BLOCK_PROPS = frozenset({"points", "z", "color", "color_rgba", "ranger_return",
                         "obstacle_return"})
_BLOCK_POINT = re.compile(r"^point\[\d+\]$")

HINTS = {
    "laser": "Stage 4 has no 'laser' type; use ranger( sensor( range [min max] fov F samples N ) )",
}


def allowed_props(entity_type: str) -> frozenset[str] | None:
    """Property names an entity of ``entity_type`` may set; None = not checked."""
    if entity_type in LOOSE_TYPES or entity_type in GUI_TYPES:
        return None
    return {
        "world": WORLD_PROPS, "position": POSITION_PROPS, "sensor": SENSOR_PROPS,
        "block": BLOCK_PROPS,
    }.get(entity_type, MODEL_PROPS)


def is_allowed(entity_type: str, name: str) -> bool:
    """True if ``name`` is a property an entity of ``entity_type`` reads."""
    allowed = allowed_props(entity_type)
    if allowed is None or name in allowed:
        return True
    return entity_type == "block" and bool(_BLOCK_POINT.match(name))


def allowed_children(parent_type: str, child_type: str) -> bool:
    """Whether ``child_type`` may be nested in ``parent_type`` (Stage's structure)."""
    if child_type in GUI_TYPES:
        return parent_type == "world"
    if child_type == "sensor":
        return parent_type == "ranger"
    if child_type == "block":
        return parent_type in MODEL_TYPES
    if parent_type in SUB_BLOCKS:
        return False
    return True
