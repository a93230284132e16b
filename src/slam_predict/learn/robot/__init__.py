"""Robot-aware models: plan features + the robot's laser and odometry → the four components.

Modules: :mod:`inputs` (the robot as four numbers, the derived plan × robot input),
:mod:`records` / :mod:`outcomes` (run records of a design campaign), :mod:`domain` (GMapping's
maxUrange, the design's bounds), :mod:`rundata` (the runs with their plan features; POINT rows
as rows of the one learning dataset),
:mod:`config` (``config/robot_learning.yaml``), :mod:`models` / :mod:`trend` /
:mod:`monotone` (the regressors on the log scale), :mod:`evaluate` (held-out buildings,
configurations or both), :mod:`train` (the model folder), :mod:`plain` (numpy-only forms),
:mod:`predict` (:class:`~slam_predict.learn.robot.predict.RobotModel`), :mod:`agreement`
(against another study's runs), :mod:`monotone_check` (no smaller error for a worse robot, on a
grid; only models that pass ship) and :mod:`failure` (the probability that an exploration
fails).

Model folders written before this package pickled their estimators under the module names
``slam_predict.learn.robot_<module>``; :func:`legacy_module_names` maps those names while a
pickle loads.
"""
from __future__ import annotations

import contextlib
import importlib
import sys
from collections.abc import Iterator

MODULES = ("agreement", "config", "domain", "evaluate", "inputs", "models",
           "monotone", "outcomes", "plain", "predict", "records", "rundata", "train", "trend")


@contextlib.contextmanager
def legacy_module_names() -> Iterator[None]:
    """While active, ``slam_predict.learn.robot_<module>`` names this package's modules (so
    pickles of older model folders load); the names are removed afterwards."""
    added = []
    for name in MODULES:
        legacy = f"slam_predict.learn.robot_{name}"
        if legacy not in sys.modules:
            sys.modules[legacy] = importlib.import_module(f"slam_predict.learn.robot.{name}")
            added.append(legacy)
    try:
        yield
    finally:
        for legacy in added:
            sys.modules.pop(legacy, None)
