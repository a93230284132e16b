"""Strict, typed configuration: dataclasses loaded from YAML, unknown keys rejected.

Every config class is a plain (frozen or not) dataclass with defaults. ``from_dict`` checks the
keys (with a did-you-mean hint), converts nested dataclasses, tuples and numbers, and
``to_dict`` gives the inverse, so ``from_dict(cls, to_dict(x)) == x``.
"""
from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import typing
from typing import Any, Dict, Mapping, Optional, Type, TypeVar

import yaml

from slam_predict.errors import InputError, did_you_mean

T = TypeVar("T")


def from_dict(cls: Type[T], data: Optional[Mapping[str, Any]], source: str = "<config>") -> T:
    """Build dataclass ``cls`` from ``data``; raise InputError naming ``source`` on bad keys."""
    data = dict(data or {})
    fields = {f.name: f for f in dataclasses.fields(cls)}
    hints = typing.get_type_hints(cls)
    kwargs: Dict[str, Any] = {}
    for key, value in data.items():
        if key not in fields:
            raise InputError(f"unknown config key '{key}' for {cls.__name__}"
                             + did_you_mean(key, fields), source)
        kwargs[key] = _convert(hints[key], value, f"{source}:{key}", source)
    try:
        return cls(**kwargs)
    except (TypeError, ValueError) as exc:
        raise InputError(f"invalid {cls.__name__}: {exc}", source) from None


def _convert(hint: Any, value: Any, where: str, source: str) -> Any:
    """Convert a YAML value to the annotated type (dataclass, tuple, float, int, Optional)."""
    origin = typing.get_origin(hint)
    args = typing.get_args(hint)
    if origin is typing.Union:
        if value is None and type(None) in args:
            return None
        hint = next(a for a in args if a is not type(None))
        return _convert(hint, value, where, source)
    if dataclasses.is_dataclass(hint):
        if not isinstance(value, Mapping):
            raise InputError(f"'{where}' must be a mapping", source)
        return from_dict(hint, value, source)
    if origin is tuple:
        if not isinstance(value, (list, tuple)):
            raise InputError(f"'{where}' must be a list", source)
        if len(args) == 2 and args[1] is Ellipsis:
            return tuple(_convert(args[0], v, where, source) for v in value)
        if len(args) != len(value):
            raise InputError(f"'{where}' needs {len(args)} values, got {len(value)}", source)
        return tuple(_convert(a, v, where, source) for a, v in zip(args, value))
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


def to_dict(obj: Any) -> Dict[str, Any]:
    """Plain-dict form of a config dataclass (tuples as lists), the inverse of ``from_dict``."""
    def plain(value: Any) -> Any:
        if dataclasses.is_dataclass(value):
            return {f.name: plain(getattr(value, f.name)) for f in dataclasses.fields(value)}
        if isinstance(value, (tuple, list)):
            return [plain(v) for v in value]
        return value
    return plain(obj)


def load_yaml(path: os.PathLike | str) -> Dict[str, Any]:
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


def load_config(cls: Type[T], path: os.PathLike | str, section: Optional[str] = None) -> T:
    """Load dataclass ``cls`` from a YAML file (optionally from one top-level ``section``)."""
    data = load_yaml(path)
    if section is not None:
        data = data.get(section, {})
    return from_dict(cls, data, os.fspath(path))


def config_hash(obj: Any) -> str:
    """Short stable hash (12 hex digits) of a config dataclass, for run metadata."""
    text = json.dumps(to_dict(obj), sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:12]
