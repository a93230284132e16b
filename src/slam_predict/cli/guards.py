"""Checks every subcommand runs on its options before any work: outputs and numeric ranges.

An output is checked before the (possibly long) computation, so a bad ``--out`` costs nothing:

* :func:`check_out_dir` — a folder the command creates or replaces: refused when it exists and
  is not empty (unless ``--force``), when it is a file, or when it cannot be created;
* :func:`check_out_file` — a file the command writes: refused when it exists (unless
  ``--force``), when it is a folder, or when it cannot be created;
* :func:`check_at_least` / :func:`check_positive` — numeric options (``--jobs ≥ 1``...).

Each failure raises :class:`~slam_predict.errors.InputError`: the CLI prints one line naming
the path and the problem and exits 2, with nothing written.
"""
from __future__ import annotations

import argparse
import os
from collections.abc import Iterable

from slam_predict.errors import InputError
from slam_predict.words import plural  # noqa: F401  (re-exported for the commands)

Number = int | float
PathArg = str | os.PathLike
FORCE_HELP = "replace an existing output (default: refuse to touch it)"


def add_force_argument(parser: argparse.ArgumentParser, help_text: str = FORCE_HELP) -> None:
    """The ``--force`` flag of a command that writes an output."""
    parser.add_argument("--force", action="store_true", help=help_text)


def check_creatable(path: PathArg, option: str = "--out") -> None:
    """InputError unless ``path``'s parent folder exists and is writable, or can be created.

    Walks up to the nearest existing ancestor: it must be a folder (a path under a file can
    never be created) that this process may write into.
    """
    path = os.fspath(path)
    ancestor = os.path.dirname(os.path.abspath(path))
    while not os.path.lexists(ancestor):
        ancestor = os.path.dirname(ancestor)
    if not os.path.isdir(ancestor):
        raise InputError(f"{option} cannot be created: {ancestor} is a file, not a folder",
                         path)
    if not os.access(ancestor, os.W_OK | os.X_OK):
        raise InputError(f"{option} cannot be created: no permission to write in {ancestor}",
                         path)


def check_out_dir(path: PathArg, force: bool, option: str = "--out",
                  inputs: Iterable[PathArg | None] = ()) -> None:
    """InputError unless ``path`` is a folder the command may create (or, with ``force``,
    replace): an existing non-empty folder is only replaced with ``--force``, and never when
    it holds the current folder or one of the command's ``inputs`` (None entries skipped)."""
    path = os.fspath(path)
    if os.path.lexists(path) and not os.path.isdir(path):
        raise InputError(f"{option} must be a folder; this exists and is not a folder", path)
    if os.path.isdir(path):
        if not force and _has_entries(path, option):
            raise InputError(f"{option} folder exists and is not empty; use --force to replace "
                             "it or choose another folder", path)
        _refuse_replacing_inputs(path, option, inputs)
    check_creatable(path, option)


def _has_entries(folder: str, option: str) -> bool:
    try:
        with os.scandir(folder) as entries:
            return next(entries, None) is not None
    except OSError as exc:
        raise InputError(f"{option} folder cannot be read ({exc.strerror or exc})",
                         folder) from None


def _refuse_replacing_inputs(path: str, option: str, inputs: Iterable[PathArg | None]) -> None:
    """InputError when replacing folder ``path`` would delete the current folder or an input."""
    folder = os.path.realpath(path)
    for item, what in [(os.getcwd(), "the current folder")] + [
            (i, f"the input {os.fspath(i)}") for i in inputs if i is not None]:
        real = os.path.realpath(item)
        if real == folder or real.startswith(folder.rstrip(os.sep) + os.sep):
            raise InputError(f"{option} holds {what}; --force would delete it: choose another "
                             "folder", path)


def check_out_file(path: PathArg, force: bool, option: str = "--out") -> None:
    """InputError unless ``path`` is a file the command may create (or, with ``force``,
    overwrite): an existing file is only replaced with ``--force``; a folder never."""
    path = os.fspath(path)
    if os.path.isdir(path):
        raise InputError(f"{option} is a folder; give the file to write", path)
    if os.path.lexists(path) and not force:
        raise InputError(f"{option} file exists; use --force to overwrite it or choose "
                         "another name", path)
    check_creatable(path, option)


def check_at_least(value: Number | None, minimum: Number, option: str) -> None:
    """InputError when ``value`` (None = not given) is below ``minimum``."""
    if value is not None and not value >= minimum:
        raise InputError(f"{option} must be ≥ {minimum:g}, got {value:g}")


def check_positive(value: Number | None, option: str) -> None:
    """InputError when ``value`` (None = not given) is not > 0 (NaN included)."""
    if value is not None and not value > 0:
        raise InputError(f"{option} must be > 0, got {value:g}")


def check_share(value: Number | None, option: str) -> None:
    """InputError when ``value`` (None = not given) is not a share in [0, 1] (NaN included)."""
    if value is not None and not 0.0 <= value <= 1.0:
        raise InputError(f"{option} must be in [0, 1], got {value:g}")
