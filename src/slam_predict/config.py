"""Strict, typed configuration: dataclasses loaded from YAML, unknown keys rejected.

Every config class is a plain (frozen or not) dataclass with defaults. ``from_dict`` checks the
keys (with a did-you-mean hint) and the value ranges a class declares in ``RANGES``, converts
nested dataclasses, tuples and numbers, and ``to_dict`` gives the inverse, so
``from_dict(cls, to_dict(x)) == x``. Every error is one line naming the file and the key path
(``sim.odom.gaussian``).

A class declares its numeric ranges as ``RANGES: ClassVar[Dict[str, Range]] = {"particles":
AT_LEAST_ONE, ...}``; a tuple field's range applies to each element, ``None`` is always allowed
(it means "not set").
"""
from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import os
import types
import typing
from collections.abc import Mapping
from typing import Any, TypeVar

import yaml

from slam_predict.errors import InputError, did_you_mean

T = TypeVar("T")


@dataclasses.dataclass(frozen=True)
class Range:
    """Allowed values of a number: ``low`` ≤ v ≤ ``high`` (None = unbounded); ``open_low`` /
    ``open_high`` make a bound strict (v > low, v < high)."""

    low: float | None = None
    high: float | None = None
    open_low: bool = False
    open_high: bool = False

    def contains(self, value: float) -> bool:
        """Whether ``value`` lies in the range (NaN never does)."""
        if math.isnan(value):
            return False
        if self.low is not None and (value <= self.low if self.open_low else value < self.low):
            return False
        if self.high is not None and (value >= self.high if self.open_high
                                      else value > self.high):
            return False
        return True

    def describe(self) -> str:
        """The range in words: '≥ 0', '> 0', 'in [0, 1]', 'in (0, 1)', '≤ 1'."""
        if self.low is not None and self.high is not None:
            return (f"in {'(' if self.open_low else '['}{self.low:g}, "
                    f"{self.high:g}{')' if self.open_high else ']'}")
        if self.low is not None:
            return f"{'>' if self.open_low else '≥'} {self.low:g}"
        if self.high is not None:
            return f"{'<' if self.open_high else '≤'} {self.high:g}"
        return "any number"


NON_NEGATIVE = Range(0.0)
POSITIVE = Range(0.0, open_low=True)
AT_LEAST_ONE = Range(1.0)
PROBABILITY = Range(0.0, 1.0)
TWO_OR_MORE = Range(2.0)
FRACTION = Range(0.0, 1.0, open_low=True, open_high=True)


def from_dict(cls: type[T], data: Mapping[str, Any] | None, source: str = "<config>",
              key_path: str = "") -> T:
    """Build dataclass ``cls`` from ``data``; raise InputError naming ``source`` and the key
    on unknown keys, wrong types and values outside ``cls.RANGES``.

    ``key_path`` is where ``data`` sits in its file (e.g. ``sim`` for the ``sim:`` section),
    used in the messages.
    """
    if data is not None and not isinstance(data, Mapping):
        raise InputError(f"'{key_path or cls.__name__}' must be a mapping, got {data!r}", source)
    data = dict(data or {})
    fields = {f.name: f for f in dataclasses.fields(cls)}
    hints = typing.get_type_hints(cls)
    ranges = getattr(cls, "RANGES", {})
    kwargs: dict[str, Any] = {}
    for key, value in data.items():
        if key not in fields:
            where = f" in '{key_path}'" if key_path else ""
            raise InputError(f"unknown config key '{key}'{where}" + did_you_mean(key, fields),
                             source)
        path = _join(key_path, key)
        kwargs[key] = _convert(hints[key], value, path, source)
        if key in ranges:
            _check_range(kwargs[key], ranges[key], path, source)
    try:
        return cls(**kwargs)
    except (TypeError, ValueError) as exc:
        name = f"'{key_path}' ({cls.__name__})" if key_path else cls.__name__
        raise InputError(f"invalid {name}: {exc}", source) from None


def check_keys(data: Mapping[str, Any], allowed, source: str, key_path: str = "") -> None:
    """InputError (with a did-you-mean) when ``data`` has a key not in ``allowed``: for the
    top level of a file that holds named sections, e.g. ``{'sim'}`` in config/robot.yaml."""
    allowed = list(allowed)
    for key in data:
        if key not in allowed:
            where = f" in '{key_path}'" if key_path else ""
            hint = did_you_mean(str(key), allowed) or " (expected {})".format(
                ", ".join(f"'{a}'" for a in allowed))
            raise InputError(f"unknown config key '{key}'{where}{hint}", source)


def _join(prefix: str, key: Any) -> str:
    return f"{prefix}.{key}" if prefix else str(key)


def _check_range(value: Any, allowed: Range, where: str, source: str) -> None:
    """InputError when a number (or any number in a tuple) lies outside ``allowed``."""
    values = value if isinstance(value, tuple) else (value,)
    for item in values:
        if isinstance(item, (int, float)) and not isinstance(item, bool) \
                and not allowed.contains(item):
            raise InputError(f"'{where}' must be {allowed.describe()}, got {item!r}", source)


def _convert(hint: Any, value: Any, where: str, source: str) -> Any:
    """Convert a YAML value to the annotated type (dataclass, tuple, float, int, Optional)."""
    origin = typing.get_origin(hint)
    args = typing.get_args(hint)
    if origin is typing.Union or origin is types.UnionType:  # Optional[X] or X | None
        if value is None and type(None) in args:
            return None
        hint = next(a for a in args if a is not type(None))
        return _convert(hint, value, where, source)
    if dataclasses.is_dataclass(hint):
        if not isinstance(value, Mapping):
            raise InputError(f"'{where}' must be a mapping", source)
        return from_dict(hint, value, source, where)
    if origin is tuple:
        if not isinstance(value, (list, tuple)):
            raise InputError(f"'{where}' must be a list", source)
        if len(args) == 2 and args[1] is Ellipsis:
            return tuple(_convert(args[0], v, f"{where}[{i}]", source)
                         for i, v in enumerate(value))
        if len(args) != len(value):
            raise InputError(f"'{where}' needs {len(args)} values, got {len(value)}", source)
        return tuple(_convert(a, v, f"{where}[{i}]", source)
                     for i, (a, v) in enumerate(zip(args, value, strict=True)))
    if hint is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise InputError(f"'{where}' must be a number, got {value!r}", source)
        return float(value)
    if hint is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise InputError(f"'{where}' must be an integer, got {value!r}", source)
        return value
    if hint is bool and not isinstance(value, bool):
        raise InputError(f"'{where}' must be true or false, got {value!r}", source)
    if hint is str and not isinstance(value, str):
        raise InputError(f"'{where}' must be a string, got {value!r}", source)
    return value


def to_dict(obj: Any) -> dict[str, Any]:
    """Plain-dict form of a config dataclass (tuples as lists), the inverse of ``from_dict``."""
    def plain(value: Any) -> Any:
        if dataclasses.is_dataclass(value):
            return {f.name: plain(getattr(value, f.name)) for f in dataclasses.fields(value)}
        if isinstance(value, (tuple, list)):
            return [plain(v) for v in value]
        return value
    return plain(obj)


def load_yaml(path: os.PathLike | str) -> dict[str, Any]:
    """Read a YAML mapping; InputError (naming the file) when missing or malformed."""
    path = os.fspath(path)
    try:
        with open(path, encoding="utf-8") as handle:
            data = yaml.safe_load(handle)
    except FileNotFoundError:
        raise InputError("config file not found", path) from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = mark.line + 1 if mark is not None else None
        raise InputError(f"YAML syntax error: {getattr(exc, 'problem', exc)}", path, line) from None
    if data is None:
        return {}
    if not isinstance(data, dict):
        raise InputError("top level must be a mapping", path)
    return data


def load_config(cls: type[T], path: os.PathLike | str, section: str | None = None) -> T:
    """Load dataclass ``cls`` from a YAML file (optionally from its one top-level ``section``;
    any other top-level key is then an error)."""
    data = load_yaml(path)
    if section is not None:
        check_keys(data, [section], os.fspath(path))
        data = data.get(section)
        if data is not None and not isinstance(data, Mapping):
            raise InputError(f"'{section}' must be a mapping", path)
    return from_dict(cls, data, os.fspath(path), section or "")


def check_ranges(section: str, config, positive=(), non_negative=()) -> None:
    """ValueError naming ``section.key`` for a value of ``config`` outside its range."""
    for key in positive:
        if not getattr(config, key) > 0:
            raise ValueError(f"{section}.{key} must be > 0, got {getattr(config, key)}")
    for key in non_negative:
        if not getattr(config, key) >= 0:
            raise ValueError(f"{section}.{key} must be >= 0, got {getattr(config, key)}")


def _hash_tree(obj: Any) -> Any:
    """``to_dict`` of ``obj`` without the fields its class lists in ``HASH_OMIT_IF`` (name →
    default) while they hold that default, so adding an option keeps older configs' hashes."""
    if dataclasses.is_dataclass(obj):
        omit = getattr(type(obj), "HASH_OMIT_IF", {})
        return {f.name: _hash_tree(getattr(obj, f.name)) for f in dataclasses.fields(obj)
                if not (f.name in omit and getattr(obj, f.name) == omit[f.name])}
    if isinstance(obj, (tuple, list)):
        return [_hash_tree(v) for v in obj]
    return obj


def config_hash(obj: Any) -> str:
    """Short stable hash (12 hex digits) of a config dataclass, for run metadata. Fields a class
    names in ``HASH_OMIT_IF`` are left out while they hold the value given there (an option added
    later whose value reproduces the behaviour from before it), so such configs keep their old
    hash and campaigns collected before can still be resumed."""
    text = json.dumps(_hash_tree(obj), sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:12]
