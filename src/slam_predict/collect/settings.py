"""Settings of a collection run, loaded from ``config/collect.yaml`` and the files it names.

A settings file may ``extends: other.yaml`` (its keys override the other file's; the file paths
of each file are relative to the file that names them) and may carry ``sim_overrides``: a partial
``sim`` section merged over the robot file's, e.g. ``{odom: {model: fixed}, laser: {range_max:
60.0}}`` — how the fidelity campaign's variants (config/fidelity/) are written — and
``nav_overrides``: move_base.yaml keys (top level) and a ``TrajectoryPlannerROS`` mapping of
base_local_planner parameters set over the navigation folder's (not the costmaps or the global
planners);
``explore_overrides``: explorer parameters (config/explore.yaml keys) set over the ``explore``
file's.

The SLAM back-end is ``slam: {type: NAME, params: FILE or {…}}``: any name of
:func:`slam_predict.slam.available`, its parameters as a YAML file (relative to the settings
file) or inline; a file that sets ``type`` without ``params`` runs the back-end's defaults. The
old ``gmapping: FILE`` key is still read as ``slam: {type: gmapping, params: FILE}``, with a
deprecation warning.

``fitted: {dotted.setting: how it was fitted}`` names the settings chosen to match the seed
study rather than measured (project rule: labelled as fitted wherever used). It changes no run
and no hash; model cards record it (``sources.fitted``) and ``predict`` shows it. A file that
extends one with a fitted setting it does not use sets that key to null.
"""
from __future__ import annotations

import dataclasses
import logging
import os
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from slam_predict.collect.stopping import StopConfig
from slam_predict.config import (
    check_ranges,
    config_hash,
    from_dict,
    load_config,
    load_yaml,
    to_dict,
)
from slam_predict.errors import InputError
from slam_predict.paths import PROJECT_ROOT
from slam_predict.slam import SlamChoice
from slam_predict.slam.compute_delay import ComputeDelayConfig

LOG = logging.getLogger(__name__)
DEFAULT_SETTINGS = PROJECT_ROOT / "config" / "collect.yaml"
# the shipped settings of each back-end (same robot, navigation, explorer and stop rule)
SLAM_SETTINGS = {"gmapping": DEFAULT_SETTINGS,
                 "karto": PROJECT_ROOT / "config" / "collect_karto.yaml"}
FILE_KEYS = ("robot", "navigation", "explore")
FILE_DEFAULTS = ("robot.yaml", ".", "explore.yaml")
DEFAULT_SLAM = {"type": "gmapping", "params": "gmapping.yaml"}


@dataclass
class MetricSettings:
    """Relations sampling of the per-run metric (m, rad)."""

    pilot: int = 500
    margin_trans: float = 0.02
    margin_rot: float = 0.002
    confidence: float = 0.99

    def __post_init__(self) -> None:
        check_ranges("metric", self, positive=("pilot", "margin_trans", "margin_rot"))
        if not 0.0 < self.confidence < 1.0:
            raise ValueError(f"metric.confidence must be in (0, 1), got {self.confidence}")


@dataclass
class SlamSection:
    """``slam:`` of collect.yaml: a registered back-end name and its parameters (the path of a
    YAML file, a mapping, or null for the back-end's defaults)."""

    type: str = "gmapping"
    params: Any = "gmapping.yaml"


@dataclass
class CollectFiles:
    """The collect.yaml file itself: references to the component configs + inline sections."""

    robot: str = "robot.yaml"
    slam: SlamSection = field(default_factory=SlamSection)
    navigation: str = "."
    explore: str = "explore.yaml"
    stop: StopConfig = field(default_factory=StopConfig)
    metric: MetricSettings = field(default_factory=MetricSettings)
    bag: bool = False
    sensor_logs: bool = False
    sim_overrides: dict[str, Any] = field(default_factory=dict)
    nav_overrides: dict[str, Any] = field(default_factory=dict)
    explore_overrides: dict[str, Any] = field(default_factory=dict)
    slam_compute: ComputeDelayConfig = field(default_factory=ComputeDelayConfig)
    fitted: dict[str, Any] = field(default_factory=dict)


@dataclass
class CollectSettings:
    """Everything one run needs besides the world and the seed."""

    sim: Any
    slam: SlamChoice
    nav: Any
    explore: Any
    stop: StopConfig
    metric: MetricSettings
    bag: bool
    source: str
    sensor_logs: bool = False
    compute: ComputeDelayConfig = field(default_factory=ComputeDelayConfig)
    fitted: dict[str, str] = field(default_factory=dict)   # not in components(): no hash

    def components(self) -> dict[str, Any]:
        """Every component config by name; the SLAM one under its back-end's name, the compute
        delay (``slam_compute``) only when it is on, so lockstep runs keep their hashes."""
        parts = {"sim": self.sim, self.slam.type: self.slam.params, "nav": self.nav,
                 "explore": self.explore, "stop": self.stop, "metric": self.metric}
        if self.compute.enabled:
            parts["slam_compute"] = self.compute
        return parts

    def hashes(self) -> dict[str, str]:
        """Short hashes of each component config, for run metadata."""
        return {name: config_hash(value) for name, value in self.components().items()}


def load_settings(path: os.PathLike | str | None = None,
                  robot: os.PathLike | str | None = None,
                  force_robot: bool = False) -> CollectSettings:
    """Load collect.yaml (default: the package's config/collect.yaml) and the files it names;
    with ``robot``, a robot description file (:mod:`slam_predict.robot_file`) applied over them
    (:func:`with_robot`), by path or shipped name; ``force_robot`` accepts an implausible one
    (:func:`~slam_predict.robot_file.load_robot`)."""
    from slam_predict.explore.explorer import ExploreConfig
    from slam_predict.nav.config import load_nav_config
    from slam_predict.sim import SimConfig

    path = Path(path or DEFAULT_SETTINGS)
    files = from_dict(CollectFiles, read_settings_tree(path), str(path))
    robot_file = Path(files.robot)
    _refuse_robot_description(robot_file, path)
    if files.sim_overrides:
        sim_tree = merge_trees(load_yaml(robot_file).get("sim", {}) or {}, files.sim_overrides)
        sim = from_dict(SimConfig, sim_tree, f"{robot_file} + {path} sim_overrides")
    else:
        sim = load_config(SimConfig, robot_file, "sim")
    settings = CollectSettings(
        sim=sim, slam=load_slam(files.slam, path),
        nav=load_nav_config(Path(files.navigation), checked_nav_overrides(files.nav_overrides,
                                                                          path)),
        explore=load_explore(ExploreConfig, Path(files.explore), files.explore_overrides, path),
        stop=files.stop, metric=files.metric, bag=files.bag, source=str(path),
        sensor_logs=files.sensor_logs, compute=files.slam_compute,
        fitted=checked_fitted(files.fitted, path))
    if robot is None:
        return settings
    from slam_predict.robot_file import load_robot, robot_path

    return with_robot(settings, load_robot(robot, force=force_robot), robot_path(robot))


def load_explore(cls, explore_file: Path, overrides: dict[str, Any], path: Path):
    """The explorer config of ``explore_file`` with a settings file's ``explore_overrides``."""
    if not overrides:
        return load_config(cls, explore_file)
    tree = merge_trees(dict(load_yaml(explore_file) or {}), overrides)
    return from_dict(cls, tree, f"{explore_file} + {path} explore_overrides")


# Sections of the move_base tree whose own parameters ``nav_overrides`` may set (a mapping),
# with the navigation folder's file that holds each.
OVERRIDABLE_NAV_SECTIONS = {"TrajectoryPlannerROS": "base_local_planner.yaml",
                            "local_costmap": "local_costmap.yaml"}


def checked_nav_overrides(overrides: dict[str, Any], path: Path) -> dict[str, Any]:
    """``nav_overrides`` when every key is a top-level move_base parameter or a mapping of
    TrajectoryPlannerROS or local_costmap parameters (the other sections are set in their own
    files); InputError otherwise."""
    from slam_predict.nav.config import MoveBaseConfig

    defaults = MoveBaseConfig()
    allowed = {f.name for f in dataclasses.fields(MoveBaseConfig)
               if not dataclasses.is_dataclass(getattr(defaults, f.name))}
    for key, value in overrides.items():
        if key in OVERRIDABLE_NAV_SECTIONS:
            names = {f.name for f in dataclasses.fields(getattr(defaults, key))}
            unknown = sorted(set(value) - names) if isinstance(value, dict) else [str(value)]
            if unknown:
                raise InputError(f"nav_overrides.{key}: not a {key} parameter: "
                                 f"{', '.join(unknown)}", path)
        elif key not in allowed:
            raise InputError(f"nav_overrides: '{key}' is not a move_base.yaml parameter (of "
                             f"the sections only {' and '.join(OVERRIDABLE_NAV_SECTIONS)} are "
                             "overridable here)", path)
    return dict(overrides)


def checked_fitted(fitted: dict[str, Any], path: Path) -> dict[str, str]:
    """The ``fitted`` entries that apply (null ones dropped); each key must name a setting:
    ``section.key`` of a settings section (``slam_compute``, ``stop``, ``metric``, ``slam``)
    or ``sim_overrides.…``; InputError otherwise."""
    out = {}
    defaults = CollectFiles()
    for key, how in fitted.items():
        section, _, name = str(key).partition(".")
        default = getattr(defaults, section, None) if section != "fitted" else None
        known = (section == "sim_overrides" and name) or (
            dataclasses.is_dataclass(default)
            and name in {f.name for f in dataclasses.fields(default)})
        if not known:
            raise InputError(f"fitted: '{key}' names no setting (section.key, e.g. "
                             "slam_compute.rebuild_s_per_line_cell)", path)
        if how is not None:
            out[str(key)] = str(how)
    return out


def fitted_settings(path: os.PathLike | str) -> dict[str, str]:
    """The fitted settings of a settings file (module doc), ``extends`` resolved."""
    path = Path(path)
    return checked_fitted(read_settings_tree(path).get("fitted") or {}, path)


def _refuse_robot_description(sim_file: Path, settings_path: Path) -> None:
    """InputError when the settings' ``robot:`` (the simulator config, a ``sim:`` section) names
    a robot description file, which belongs to ``--robot``."""
    data = load_yaml(sim_file) if sim_file.is_file() else None
    if isinstance(data, dict) and "sim" not in data and "laser" in data:
        raise InputError(f"'robot: {sim_file}' is a robot description file; the settings' "
                         f"robot: names the simulator config (a file with a sim: section, "
                         f"config/robot.yaml): give a robot description as --robot", settings_path)


def with_robot(settings: CollectSettings, robot, robot_path: str) -> CollectSettings:
    """``settings`` for the robot of a :class:`~slam_predict.robot_file.RobotDescription`: its
    ``sim_overrides`` merged over the simulator config (last, after the settings' own), its
    ``nav_overrides`` and ``explore_overrides`` over the navigation and exploration configs
    and, for GMapping, its range caps. InputError naming ``robot_path`` when the result is
    invalid (e.g. max_vel_x below the planner's min_vel_x)."""
    from slam_predict.nav.config import MoveBaseConfig
    from slam_predict.sim import SimConfig

    sim = from_dict(SimConfig, merge_trees(to_dict(settings.sim), robot.sim_overrides()),
                    robot_path, "sim")
    nav = from_dict(MoveBaseConfig, merge_trees(to_dict(settings.nav), robot.nav_overrides()),
                    robot_path)
    explore = from_dict(type(settings.explore), merge_trees(to_dict(settings.explore),
                                                            robot.explore_overrides()),
                        robot_path)
    planner = nav.TrajectoryPlannerROS
    if planner.max_vel_x < planner.min_vel_x:
        raise InputError(f"max_vel_x {robot.max_vel_x} m/s is below the planner's min_vel_x "
                         f"{planner.min_vel_x} m/s", robot_path)
    if planner.max_vel_theta < planner.min_in_place_vel_theta:
        raise InputError(f"max_vel_theta {robot.max_vel_theta} rad/s is below the planner's "
                         f"min_in_place_vel_theta {planner.min_in_place_vel_theta} rad/s",
                         robot_path)
    slam = settings.slam
    if slam.type == "gmapping":
        slam = dataclasses.replace(slam, params=robot.gmapping_caps(slam.params))
    return dataclasses.replace(settings, sim=sim, nav=nav, explore=explore, slam=slam)


def load_slam(section: SlamSection, settings_path: Path) -> SlamChoice:
    """The back-end and its parameters a settings file's ``slam:`` names."""
    from slam_predict import slam

    try:
        slam.backend_class(section.type)
    except InputError as exc:
        raise InputError(f"slam.type: {exc.problem}", settings_path) from None
    params = section.params
    if isinstance(params, str):
        return SlamChoice(section.type, slam.load_params(section.type, Path(params)))
    if params is not None and not isinstance(params, dict):
        raise InputError("slam.params must be a file name, a mapping or null", settings_path)
    return SlamChoice(section.type, slam.params_from_dict(section.type, params,
                                                          f"{settings_path} slam.params"))


def _slam_section(tree: dict[str, Any], path: Path) -> None:
    """Normalise one file's SLAM keys in place: the deprecated ``gmapping: FILE`` becomes
    ``slam: {type: gmapping, params: FILE}``; a params file name is made absolute."""
    if "gmapping" in tree:
        if "slam" in tree:
            raise InputError("both 'slam' and the deprecated 'gmapping' key are set", path)
        message = (f"{path}: 'gmapping: FILE' is deprecated; write "
                   "'slam: {type: gmapping, params: FILE}'")
        warnings.warn(message, DeprecationWarning, stacklevel=3)
        LOG.warning(message)
        tree["slam"] = {"type": "gmapping", "params": tree.pop("gmapping")}
    section = tree.get("slam")
    if not isinstance(section, dict):
        return
    section = tree["slam"] = dict(section)
    if "type" in section and "params" not in section:
        section["params"] = None   # another back-end: not the parent's parameters
    if isinstance(section.get("params"), str):
        section["params"] = str(path.parent / section["params"])


def read_settings_tree(path: Path, seen: set[Path] | None = None) -> dict[str, Any]:
    """The settings mapping of ``path`` with ``extends`` resolved and file keys made absolute."""
    path = Path(path).resolve()
    seen = set() if seen is None else seen
    if path in seen:
        raise InputError("settings 'extends' loop", path)
    seen.add(path)
    tree = dict(load_yaml(path))
    parent = tree.pop("extends", None)
    for key in FILE_KEYS:
        if key in tree:
            tree[key] = str(path.parent / str(tree[key]))
    _slam_section(tree, path)
    if parent is None:
        base = {key: str(path.parent / default)
                for key, default in zip(FILE_KEYS, FILE_DEFAULTS, strict=False)}
        base["slam"] = dict(DEFAULT_SLAM, params=str(path.parent / DEFAULT_SLAM["params"]))
        return merge_trees(base, tree)
    parent_path = path.parent / str(parent)
    if not parent_path.is_file():
        raise InputError(f"'extends' names a missing file {parent_path}", path)
    return merge_trees(read_settings_tree(parent_path, seen), tree)


def merge_trees(base: dict[str, Any], override: dict[str, Any]) -> dict[str, Any]:
    """``base`` with ``override``'s keys replacing its own; nested mappings merged key by key."""
    merged = dict(base)
    for key, value in override.items():
        if isinstance(value, dict) and isinstance(merged.get(key), dict):
            merged[key] = merge_trees(merged[key], value)
        else:
            merged[key] = value
    return merged


def settings_dict(settings: CollectSettings) -> dict[str, Any]:
    """Plain-dict form of every component config (recorded beside run.json)."""
    return {name: to_dict(value) for name, value in settings.components().items()}


def settings_for_slam(name: str | None, settings_path=None, option: str = "--slam"):
    """The settings file for back-end ``name`` (``slam_toolbox`` = ``karto``): the given
    ``settings_path`` when its ``slam.type`` is that back-end (InputError naming both when it is
    another), else the shipped settings of the back-end; ``name`` None: ``settings_path``."""
    from slam_predict import slam

    if name is None:
        return settings_path
    name = slam.canonical_name(name, option)
    if settings_path is None:
        if name not in SLAM_SETTINGS:
            raise InputError(f"{option} {name}: no shipped settings for this back-end; give "
                             "--settings with slam.type: " + name)
        return str(SLAM_SETTINGS[name])
    found = read_settings_tree(Path(settings_path))["slam"]["type"]
    if found != name:
        raise InputError(f"slam.type is {found}, not {name} ({option}); leave {option} out or "
                         f"use settings with slam.type: {name}", settings_path)
    return settings_path
