"""What the robot inputs span: the SLAM back-end's usable laser range and the design's box.

**maxUrange.** GMapping never uses a beam beyond ``maxUrange`` (config/gmapping.yaml: 30 m;
the seed study's robot has an 80 m laser): every reading is cropped there before it is matched
or marks the map. So the models' range input is min(laser range_max, maxUrange)
(:func:`~slam_predict.learn.robot.inputs.effective_range`), with the maxUrange of the GMapping
settings the runs were collected with — the settings' own value, before the collection caps it
per robot at range_max − 0.01 (:func:`slam_predict.robot_file.gmapping_caps`). Per run
(:class:`MaxUrangeSource`) it is ``robot_learning.max_urange_m`` when set, else read from the
run's settings file (run.json ``settings_file``, relative to the project root unless absolute),
loaded once per file; its GMapping parameters, capped for the run's laser as the collection
did (or not capped, for a run collected without a robot file), must hash to the run's recorded
``config_hashes.gmapping``, else the file has changed since the run (one-line error: set
``max_urange_m``). run.json records the parameters' hash only (``slam.params_hash``), not the
parameters. Every run must give the same value; the card records it as ``max_urange_m`` and
prediction applies it to the user's robot.

**Karto.** slam_toolbox's Karto uses no reading beyond ``max_laser_range`` (config/karto.yaml:
20 m) and the collection does not change it per robot (the range finder caps itself at the
laser's range_max), so for a Karto run the cap is the settings file's ``max_laser_range``; its
Karto parameters must hash to the run's ``config_hashes.karto``. The card's field keeps its
name, ``max_urange_m``: the range cap of the back-end the model was trained for.

**Design box.** With the campaign's design file(s) (``learn robots --design``), the robot inputs'
training ranges are the design's bounds (range 3.5–30 m, fov 180–360°, odometry 0–2 × the base
robot's bounds), not only the span of the configurations drawn from them: a Latin hypercube
covers its box, and the seed study's robot (80 m laser, so 30 m used) sits at its edge
(:func:`design_ranges`). The design's configurations are checked against the runs' inputs;
runs collected without the design (no ``design`` entry in run.json, e.g. the fidelity
campaign's seed robot) may join when their inputs lie inside the bounds. Design files that
differ only in their angular resolution (the same box at 0.25°, 0.5° and 1°) pool when the
model learns the resolution (``robot_learning.resolution_input``); its range is then theirs.
"""
from __future__ import annotations

import logging
import math
import os
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from slam_predict.collect.campaign import recorded_settings_file
from slam_predict.errors import InputError
from slam_predict.learn.card import SLAM_ALGORITHMS, slam_label
from slam_predict.learn.robot.inputs import (
    ALL_ROBOT_INPUTS,
    RESOLUTION_INPUT,
    ROBOT_INPUTS,
    inputs_from_robot,
    resolution_input_value,
)

LOG = logging.getLogger(__name__)
HINT = ("set robot_learning.max_urange_m to the range cap (m: GMapping's maxUrange, Karto's "
        "max_laser_range) the runs were collected with")


def settings_cap(params) -> float | None:
    """The range cap of GMapping parameters, m: maxUrange, else maxRange (slam_gmapping sets
    maxUrange = maxRange when unset), else None (both unset: the laser's own range)."""
    for value in (params.maxUrange, params.maxRange):
        if value is not None:
            return float(value)
    return None


def _laser_range(record: Mapping[str, Any], path) -> float:
    try:
        value = record["sensor"]["laser"]["range_max"]
    except (KeyError, TypeError):
        raise InputError("sensor has no 'laser.range_max'", path) from None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(f"sensor 'laser.range_max' must be a finite number, got {value!r}", path)
    return float(value)


class MaxUrangeSource:
    """maxUrange (m, or None: no cap) of the GMapping settings of each run (module doc).

    Args:
        override: ``robot_learning.max_urange_m``; when not None every run gets it.
        root: folder a relative ``settings_file`` is taken from (the project root).
    """

    def __init__(self, override: float | None = None, root: os.PathLike | str | None = None):
        from slam_predict.paths import PROJECT_ROOT

        self.override = override
        self.root = Path(root) if root is not None else PROJECT_ROOT
        self._params: dict[str, Any] = {}

    def of_record(self, record: Mapping[str, Any], path) -> float | None:
        """The maxUrange of the settings a run record was collected with; InputError naming
        ``path`` when it cannot be told."""
        if self.override is not None:
            return float(self.override)
        slam = record.get("slam") if isinstance(record.get("slam"), Mapping) else {}
        backend = slam.get("type", "gmapping")
        if backend not in SLAM_ALGORITHMS:
            raise InputError(f"run of SLAM back-end '{backend}': the robot-aware models learn "
                             "GMapping and Karto runs", path)
        hashes = record.get("config_hashes")
        recorded = (hashes.get(backend) if isinstance(hashes, Mapping) else None) \
            or slam.get("params_hash")
        settings_file = record.get("settings_file")
        if not isinstance(settings_file, str) or not settings_file or not recorded:
            raise InputError(f"run record names no settings_file or {slam_label(backend)} config "
                             f"hash: cannot tell the SLAM back-end's range cap; {HINT}", path)
        settings_file = self.existing_settings_file(settings_file, path)
        params = self.params(settings_file, path, backend)
        if backend == "karto":
            _check_karto_hash(params, str(recorded), settings_file, path)
            return float(params.max_laser_range)
        self._check_hash(params, _laser_range(record, path), str(recorded), settings_file, path)
        return settings_cap(params)

    def existing_settings_file(self, settings_file: str, path) -> str:
        """The run's settings file, or, when that file is gone (e.g. a probe file removed
        since), the one its campaign's campaign.json names (the run's config hash is checked
        against it all the same)."""
        file = Path(settings_file)
        if (file if file.is_absolute() else self.root / file).is_file():
            return settings_file
        campaign = Path(path).resolve().parent.parent.parent   # CAMPAIGN/WORLD/run_NNN/run.json
        recorded = recorded_settings_file(campaign)
        if recorded is None:
            return settings_file
        LOG.info("%s: settings file %s gone; the campaign's campaign.json names %s", path,
                 settings_file, recorded)
        return recorded

    def params(self, settings_file: str, path, backend: str = "gmapping"):
        """The SLAM parameters (of back-end ``backend``) of a settings file (loaded once)."""
        if settings_file not in self._params:
            from slam_predict.collect.settings import load_settings

            file = Path(settings_file)
            file = file if file.is_absolute() else self.root / file
            if not file.is_file():
                raise InputError(f"settings file {settings_file} of the run not found "
                                 f"(looked for {file}); {HINT}", path)
            try:
                settings = load_settings(file)
            except InputError as exc:
                raise InputError(f"settings file {settings_file} of the run: {exc.one_line()}",
                                 path) from None
            if settings.slam.type != backend:
                raise InputError(f"settings file {settings_file} runs SLAM back-end "
                                 f"'{settings.slam.type}' but the run ran '{backend}'", path)
            LOG.info("%s parameters of %s loaded", backend, settings_file)
            self._params[settings_file] = settings.slam.params
        return self._params[settings_file]

    @staticmethod
    def _check_hash(params, range_max: float, recorded: str, settings_file: str, path) -> None:
        """InputError unless the settings' parameters (capped for the run's laser, or as they
        are) hash to the run's recorded GMapping config hash."""
        from slam_predict.config import config_hash
        from slam_predict.robot_file import gmapping_caps

        hashes = {config_hash(gmapping_caps(params, range_max)), config_hash(params)}
        if recorded not in hashes:
            raise InputError(f"settings file {settings_file} gives GMapping config "
                             f"{config_hash(gmapping_caps(params, range_max))} for the run's "
                             f"{range_max:g} m laser, the run recorded {recorded} (has the file "
                             f"changed since?); {HINT}", path)


def _check_karto_hash(params, recorded: str, settings_file: str, path) -> None:
    """InputError unless the settings' Karto parameters hash to the run's recorded one."""
    from slam_predict.config import config_hash

    if config_hash(params) != recorded:
        raise InputError(f"settings file {settings_file} gives Karto config "
                         f"{config_hash(params)}, the run recorded {recorded} (has the file "
                         f"changed since?); {HINT}", path)


def common_max_urange(values: Mapping[str, float | None]) -> float | None:
    """The one maxUrange of runs (source file → value); InputError naming two runs that
    differ (the range input would mean different things)."""
    items = list(values.items())
    if not items:
        return None
    first_source, first = items[0]
    for source, value in items[1:]:
        if value != first:
            raise InputError(f"runs collected with different GMapping maxUrange: "
                             f"{_text(value)} here, {_text(first)} in {first_source}", source)
    return first


def _text(value: float | None) -> str:
    return "unset (the laser's range)" if value is None else f"{value:g} m"


def design_ranges(paths, max_urange_m: float | None,
                  configs: Mapping[str, Mapping[str, float]],
                  undesigned: Iterable[str] = (),
                  resolution_input: bool = False) -> dict[str, list[float]]:
    """Robot input → [low, high] of the bounds of one design file or several (``paths``: a
    path or a sequence of them, e.g. a campaign's design and an extension's that adds
    configurations), in the inputs' units (range capped at ``max_urange_m``); InputError
    naming a file when a configuration of the runs (``configs``: id → robot inputs) is in none
    of them or has other inputs there, when two files define a configuration id differently,
    or when they disagree on the bounds, the base robot or (unless ``resolution_input``) the
    angular resolution; ``laser_resolution_deg`` spans the files' resolutions. The
    configurations named in ``undesigned`` (runs collected without the design, e.g. with the
    seed robot's file) need not be in a file but must lie inside the bounds."""
    from slam_predict.collect.robot_design import FACTORS, configured_robot

    first_path, first, robots, resolutions = _pooled_designs(paths, resolution_input)
    corners = [inputs_from_robot(configured_robot(first.base,
                                                  {f: first.bounds[f][i] for f in FACTORS},
                                                  first.resolution_deg, f"bound{i}"),
                                 max_urange_m) for i in (0, 1)]
    ranges = {name: [min(c[name] for c in corners), max(c[name] for c in corners)]
              for name in ROBOT_INPUTS}
    ranges[RESOLUTION_INPUT] = [min(resolutions), max(resolutions)]
    outside = set(undesigned)
    for config, inputs in configs.items():
        if config in outside:
            _check_inside(config, inputs, ranges, first_path)
            continue
        if config not in robots:
            raise InputError(f"configuration '{config}' of the runs is not in the design",
                             first_path)
        path, robot = robots[config]
        expected = inputs_from_robot(robot, max_urange_m)
        for name in ALL_ROBOT_INPUTS:
            if not math.isclose(expected[name], inputs[name], rel_tol=1e-6, abs_tol=1e-9):
                raise InputError(f"configuration '{config}': {name} is {expected[name]:.6g} in "
                                 f"the design, {inputs[name]:.6g} in the runs", path)
    return ranges


def _check_inside(config: str, inputs: Mapping[str, float],
                  ranges: Mapping[str, Sequence[float]], path) -> None:
    """InputError unless a configuration collected outside the design lies inside its bounds
    (relative tolerance 1e-6)."""
    for name in ALL_ROBOT_INPUTS:
        low, high = ranges[name]
        slack = 1e-6 * max(abs(low), abs(high), 1e-9)
        if not low - slack <= inputs[name] <= high + slack:
            raise InputError(f"configuration '{config}' (runs collected without the design): "
                             f"{name} {inputs[name]:.6g} lies outside the design's bounds "
                             f"[{low:.6g}, {high:.6g}]", path)
    LOG.info("configuration %s: collected without the design, inside its bounds", config)


def _pooled_designs(paths, resolution_input: bool = False):
    """(first path, its design, configuration id → (path, robot) over every file, the files'
    angular resolutions rounded to 0.01 deg); InputError when a file's bounds or base robot
    differ from the first's, its resolution does without ``resolution_input``, or two files
    define one configuration id differently."""
    from slam_predict.collect.robot_design import load_design

    files = [paths] if isinstance(paths, (str, os.PathLike)) else list(paths)
    designs = [(path, load_design(path)) for path in files]
    first_path, first = designs[0]
    robots: dict = {}
    for path, design in designs:
        if (design.bounds, design.base) != (first.bounds, first.base):
            raise InputError(f"its bounds or base robot differ from {first_path}'s", path)
        if design.resolution_deg != first.resolution_deg and not resolution_input:
            raise InputError(f"its angular resolution ({design.resolution_deg:g} deg) differs "
                             f"from {first_path}'s ({first.resolution_deg:g} deg): set "
                             "robot_learning.resolution_input: true to learn it", path)
        for config in design.configs:
            robot = design.robot(config)
            if robots.setdefault(config, (path, robot))[1] != robot:
                raise InputError(f"configuration '{config}' differs from "
                                 f"{robots[config][0]}'s", path)
    return first_path, first, robots, [resolution_input_value(d.resolution_deg) for _, d in designs]
