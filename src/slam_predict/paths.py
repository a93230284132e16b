"""The project's own folders, and paths written into records so that they stay valid in any clone.

Run records name the world and settings files they were made from. Written as absolute paths they
point into whichever clone collected them (and break in every other one), so files inside the
project are recorded relative to its root (``config/collect.yaml``, ``worlds/office_500.world``,
``out/thesis_worlds/X.world``); files elsewhere keep their absolute path.
"""
from __future__ import annotations

import os
from pathlib import Path

PROJECT_ROOT = Path(__file__).resolve().parents[2]


def portable_path(path: os.PathLike | str) -> str:
    """``path`` relative to :data:`PROJECT_ROOT` (POSIX separators) when it lies inside the
    project, else its absolute form; an empty path stays empty."""
    if not str(path):
        return ""
    absolute = Path(path).resolve()
    try:
        return absolute.relative_to(PROJECT_ROOT).as_posix()
    except ValueError:
        return str(absolute)
