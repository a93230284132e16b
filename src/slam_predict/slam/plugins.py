"""Loading SLAM back-ends that live outside slam_predict (docs/architecture.md "Adding a SLAM
back-end").

A back-end module calls :func:`slam_predict.slam.register` at import. It is found either

- by name in ``$SLAM_PREDICT_EXTRA_BACKENDS``: comma-separated entries, each a module name
  (``my_pkg.my_slam``) or the path of a ``.py`` file; every process that reads the registry
  (CLI, nodes started by roslaunch, batch workers) imports them, so a launch file can set it
  with ``<env>``; or
- as an entry point of group ``slam_predict.slam_backends`` of an installed package (the entry
  point's object is loaded, which imports its module).

A module that cannot be imported is an :class:`~slam_predict.errors.InputError` naming it.
"""
from __future__ import annotations

import importlib
import importlib.util
import logging
import sys
from pathlib import Path

from slam_predict.errors import InputError

LOG = logging.getLogger(__name__)


def import_plugins(spec: str, group: str) -> None:
    """Import every module of ``spec`` (comma-separated names or .py paths), then load the
    entry points of ``group``."""
    for entry in (part.strip() for part in spec.split(",")):
        if entry:
            _import_entry(entry)
    for point in _entry_points(group):
        try:
            point.load()
        except Exception as exc:  # a broken third-party package must not hide the cause
            raise InputError(f"SLAM back-end entry point '{point.name}' failed to load: "
                             f"{exc}") from None


def _import_entry(entry: str) -> None:
    try:
        if entry.endswith(".py"):
            _import_file(Path(entry))
        else:
            importlib.import_module(entry)
    except (ImportError, OSError) as exc:
        raise InputError(f"cannot import SLAM back-end module '{entry}' "
                         f"(SLAM_PREDICT_EXTRA_BACKENDS): {exc}") from None
    LOG.debug("SLAM back-end module %s imported", entry)


def _import_file(path: Path) -> None:
    name = f"slam_predict_backend_{path.stem}"
    if name in sys.modules:
        return
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None or not path.is_file():
        raise ImportError(f"no such file {path}")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[name]
        raise


def _entry_points(group: str):
    from importlib.metadata import entry_points

    return list(entry_points(group=group))
