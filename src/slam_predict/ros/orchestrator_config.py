"""Configuration of the orchestrator node: config/orchestrator.yaml and its ~params.

``OrchestratorConfig`` is the YAML file (ground-truth source, tf frames, sampling, explorer-end
detection, timeouts); :func:`read_setup` reads the node's private params (see
:mod:`slam_predict.ros.orchestrator_node`) into a :class:`RunSetup`.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from pathlib import Path
from typing import ClassVar

from slam_predict.config import NON_NEGATIVE, POSITIVE, Range
from slam_predict.paths import PROJECT_ROOT
from slam_predict.ros.ground_truth import GroundTruthConfig
from slam_predict.ros.orchestrator import MonitorSettings

DEFAULT_CONFIG = PROJECT_ROOT / "config" / "orchestrator.yaml"


@dataclass
class FramesConfig:
    """tf frames of the SLAM and odometry poses."""

    map: str = "map"
    odom: str = "odom"
    base: str = "base_link"


@dataclass
class ExplorerConfig:
    """How the end of exploration is detected: a log line of the explorer node on /rosout."""

    node: str = "/explore"
    stopped_text: str = "Exploration stopped"


@dataclass
class OrchestratorConfig:
    """config/orchestrator.yaml."""

    ground_truth: GroundTruthConfig = field(default_factory=GroundTruthConfig)
    frames: FramesConfig = field(default_factory=FramesConfig)
    sampling: MonitorSettings = field(default_factory=MonitorSettings)
    explorer: ExplorerConfig = field(default_factory=ExplorerConfig)
    map_topic: str = "map"
    map_odom_hold_s: float = 1.0
    finish_timeout_s: float = 30.0
    startup_timeout_s: float = 120.0
    RANGES: ClassVar[dict[str, Range]] = {
        "map_odom_hold_s": NON_NEGATIVE, "finish_timeout_s": POSITIVE,
        "startup_timeout_s": POSITIVE}


def load_orchestrator_config(path, overrides: dict) -> OrchestratorConfig:
    """config/orchestrator.yaml plus non-empty ``ground_truth`` overrides (launch args)."""
    from slam_predict.config import load_config
    from slam_predict.errors import InputError

    config = load_config(OrchestratorConfig, path)
    changes = {k: v for k, v in overrides.items() if v not in ("", None)}
    if changes:
        try:
            gt = dataclasses.replace(config.ground_truth, **changes)
        except ValueError as exc:
            raise InputError(str(exc), str(path)) from None
        config = dataclasses.replace(config, ground_truth=gt)
    return config


@dataclass
class RunSetup:
    """Everything :func:`main` reads from the parameter server and the config files."""

    out: Path
    info: object
    settings: object
    stop: object
    config: OrchestratorConfig
    world: object
    free_area_m2: float | None
    sim_node: str
    wait_for_nodes: tuple = ()


def without_compute_delay(settings, rospy_module):
    """Settings with ``slam_compute`` off: under ROS GMapping's compute time is real, so the
    in-process engine's emulation of it does not apply (and is not recorded)."""
    from slam_predict.slam.compute_delay import ComputeDelayConfig

    if not settings.compute.enabled:
        return settings
    rospy_module.logwarn("slam_compute (%s) applies to the in-process engine only; under ROS "
                         "GMapping's compute time is real", settings.compute.model)
    return dataclasses.replace(settings, compute=ComputeDelayConfig())


def read_setup(rospy_module) -> RunSetup:
    """Params → configs, world and run identity (InputError on bad input)."""
    from slam_predict.collect.record import RunInfo
    from slam_predict.collect.settings import load_settings
    from slam_predict.errors import InputError
    from slam_predict.world.load import load_plan

    get = rospy_module.get_param
    out = str(get("~out", ""))
    if not out:
        raise InputError("~out (the run folder) is not set")
    settings = without_compute_delay(load_settings(get("~settings", "") or None), rospy_module)
    config = load_orchestrator_config(get("~config", "") or DEFAULT_CONFIG, {
        "source": get("~ground_truth_source", ""), "topic": get("~ground_truth_topic", ""),
        "frame": get("~ground_truth_frame", ""),
        "fixed_frame": get("~ground_truth_fixed_frame", "")})
    world_file = str(get("~world_file", ""))
    world = load_plan(world_file) if world_file else None
    free_area = world.free_area_m2 if world is not None else float(get("~free_area_m2", 0.0))
    free_area = free_area if free_area and free_area > 0 else None  # unknown: 600 s snapshots
    changes = {}
    for key, name in (("max_sim_time_s", "~max_sim_time"), ("max_wall_time_s", "~max_wall_time")):
        if float(get(name, 0.0)) > 0:
            changes[key] = float(get(name))
    if float(get("~snapshot_interval", 0.0)) > 0:
        changes["interval_s"] = changes["small_interval_s"] = float(get("~snapshot_interval"))
    stop = dataclasses.replace(settings.stop, **changes)
    name = str(get("~world_name", "")) or (Path(world_file).stem if world_file else "robot")
    graph = {k: str(get(f"~{k}", "")) for k in ("sim", "slam", "nav", "explore")}
    info = RunInfo(world=name, world_file=world_file, run_index=int(get("~run_index", 0)),
                   seed=int(get("~seed", 0)), odometry_model=str(get("~odometry_model", "")),
                   ros={"graph": graph})
    return RunSetup(Path(out), info, settings, stop, config, world,
                    None if free_area is None else float(free_area),
                    str(get("~sim_node", "/stage_sim")),
                    tuple(str(get("~wait_for_nodes", "")).replace(",", " ").split()))
