"""Stage 4 world files: lexer, parser (include/define/inheritance), World mapping, writer.

``read_world(path)`` parses a ``.world`` file into a :class:`~slam_predict.world.model.World`;
``write_world(world, path)`` writes one (plus its 0/255 PNG) that Stage and ``read_world`` load.
"""
from __future__ import annotations

import os

from slam_predict.world.bitmap import FREE_THRESHOLD
from slam_predict.world.model import World
from slam_predict.world.stagefile.parser import Entity, Prop, parse_file
from slam_predict.world.stagefile.writer import write_world

__all__ = ["read_world", "write_world", "parse_world_file", "Entity", "Prop"]


def parse_world_file(path: os.PathLike | str) -> Entity:
    """The checked entity tree of a world file: syntax, macro types and property names."""
    from slam_predict.world.stagefile.values import check_properties

    root = parse_file(path)
    check_properties(root)
    return root


def read_world(path: os.PathLike | str, free_threshold: int = FREE_THRESHOLD) -> World:
    """Load a Stage world file as a World (start pose as given; see mapping for the rules)."""
    from slam_predict.world.stagefile.mapping import to_world
    from slam_predict.world.stagefile.values import read_units

    root = parse_world_file(path)
    return to_world(root, read_units(root), os.path.abspath(os.fspath(path)), free_threshold)
