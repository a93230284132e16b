"""Typed reading of entity properties, with Stage's units and its tuple rules.

Like Stage's ``Worldfile::ReadTuple(format)``, a tuple is read with a format string of one
letter per element: ``l`` length (× unit_length), ``a`` angle (× unit_angle; degrees by
default, so × π/180), ``f`` plain float, ``i`` integer, ``s`` string. A tuple shorter than the
format is an error (Stage exits on it); extra elements are ignored, as in Stage.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from slam_predict.errors import InputError, did_you_mean
from slam_predict.world.stagefile import schema
from slam_predict.world.stagefile.lexer import NUMBER, Token
from slam_predict.world.stagefile.parser import Entity, Prop

_LENGTH_UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001}
_ANGLE_UNITS = {"degrees": math.pi / 180.0, "radians": 1.0}


@dataclass(frozen=True)
class Units:
    """Scale factors to metres and radians (Stage's ``unit_length`` / ``unit_angle``)."""

    length: float = 1.0
    angle: float = math.pi / 180.0


def _where(token: Token):
    return token.path, token.line


def _number(token: Token, prop: Prop, integer: bool = False) -> float:
    if token.kind != NUMBER:
        raise InputError(f"property '{prop.name}' needs a number, got \"{token.text}\"",
                         *_where(token))
    try:
        value = float(token.text)
    except ValueError:
        raise InputError(f"property '{prop.name}': '{token.text}' is not a number",
                         *_where(token)) from None
    if integer:
        if value != int(value):
            raise InputError(f"property '{prop.name}' needs an integer, got {token.text}",
                             *_where(token))
        return int(value)
    return value


def _convert(token: Token, letter: str, prop: Prop, units: Units):
    if letter == "s":
        return token.text
    if letter == "i":
        return _number(token, prop, integer=True)
    value = _number(token, prop)
    if letter == "l":
        return value * units.length
    if letter == "a":
        return value * units.angle
    return value


def read_tuple(entity: Entity, name: str, fmt: str, units: Units,
               default: Sequence | None = None) -> tuple | None:
    """The values of tuple property ``name`` converted by ``fmt``, or ``default`` if unset."""
    prop = entity.props.get(name)
    if prop is None:
        return None if default is None else tuple(default)
    if len(prop.values) < len(fmt):
        raise InputError(f"property '{name}' needs {len(fmt)} values, got {len(prop.values)}",
                         *_where(prop.token))
    return tuple(_convert(tok, letter, prop, units)
                 for tok, letter in zip(prop.values, fmt, strict=False))


def read_value(entity: Entity, name: str, letter: str, units: Units, default=None):
    """A single-valued property converted by ``letter`` (see module doc), or ``default``."""
    prop = entity.props.get(name)
    if prop is None:
        return default
    if not prop.values:
        raise InputError(f"property '{name}' has no value", *_where(prop.token))
    return _convert(prop.values[0], letter, prop, units)


def read_units(root: Entity) -> Units:
    """The file's ``unit_length`` and ``unit_angle`` (defaults m and degrees)."""
    length = read_value(root, "unit_length", "s", Units(), "m")
    angle = read_value(root, "unit_angle", "s", Units(), "degrees")
    for value, table, name in ((length, _LENGTH_UNITS, "unit_length"),
                               (angle, _ANGLE_UNITS, "unit_angle")):
        if value not in table:
            prop = root.props[name]
            raise InputError(f"{name} \"{value}\" is not one of {sorted(table)}"
                             + did_you_mean(value, table), *_where(prop.token))
    return Units(_LENGTH_UNITS[length], _ANGLE_UNITS[angle])


def check_properties(root: Entity) -> None:
    """Raise InputError (with a did-you-mean hint) on a property the entity's type never reads."""
    for entity, _ in root.walk():
        allowed = schema.allowed_props(entity.type)
        if allowed is None:
            continue
        for prop in entity.props.values():
            if not schema.is_allowed(entity.type, prop.name):
                where = "the world" if entity.type == "world" else f"{entity.label} ({entity.type})"
                raise InputError(f"unknown property '{prop.name}' in {where}"
                                 + did_you_mean(prop.name, allowed), *_where(prop.token))
