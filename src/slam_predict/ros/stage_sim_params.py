"""``stage_sim``'s private ROS parameters: the world file, the simulator config and the node's
pacing, watchdog and lockstep settings (their meaning: :mod:`slam_predict.ros.stage_sim_node`).

Every function takes the ``rospy`` module (injected, so tests run without a master).
"""
from __future__ import annotations

import sys
from dataclasses import dataclass


@dataclass
class NodeSettings:
    """Node behaviour (the node's private params); see :mod:`slam_predict.ros.stage_sim_node`."""

    watchdog_timeout: float = 0.2
    speedup: float = 1.0
    lockstep: bool = True
    lockstep_timeout: float = 0.05
    laser_z: float = 0.0
    ground_truth_frame_id: str = "odom"
    lockstep_acks: tuple[tuple[str, float | None], ...] = ()  # (topic, lag s | None = scan)
    lockstep_ack_timeout: float = 30.0


def world_argument(rospy_module) -> str:
    """The world file: first non-flag command-line argument (as stageros), else ``~world``."""
    args = [a for a in rospy_module.myargv(sys.argv)[1:] if not a.startswith("-")]
    return args[0] if args else rospy_module.get_param("~world", "")


def sim_config(rospy_module):
    """SimConfig from ``~config`` (section ``sim``), then ``~odom_model``/``~integrator``."""
    import dataclasses

    from slam_predict.config import load_config
    from slam_predict.errors import InputError
    from slam_predict.sim import SimConfig

    path = rospy_module.get_param("~config", "")
    config = load_config(SimConfig, path, "sim") if path else SimConfig()
    model = rospy_module.get_param("~odom_model", "")
    integrator = rospy_module.get_param("~integrator", "")
    try:
        if model:
            config = dataclasses.replace(config, odom=dataclasses.replace(config.odom,
                                                                          model=model))
        if integrator:
            config = dataclasses.replace(config, integrator=integrator)
    except ValueError as exc:
        raise InputError(str(exc), path or None) from None
    return config


def node_settings(rospy_module) -> NodeSettings:
    """The node's pacing, watchdog and lockstep params (module docstring of
    :mod:`slam_predict.ros.stage_sim_node`)."""
    get = rospy_module.get_param
    speedup = float(get("~speedup", 1.0))
    return NodeSettings(
        watchdog_timeout=float(get("~base_watchdog_timeout", 0.2)),
        speedup=max(speedup, 0.0),
        lockstep=bool(get("~lockstep", True)),
        lockstep_timeout=float(get("~lockstep_timeout", 0.05)),
        laser_z=float(get("~laser_z", 0.0)),
        ground_truth_frame_id=str(get("~ground_truth_frame_id", "odom")),
        lockstep_acks=ack_list(get("~lockstep_acks", [])),
        lockstep_ack_timeout=float(get("~lockstep_ack_timeout", 30.0)))


def ack_list(value) -> tuple[tuple[str, float | None], ...]:
    """``~lockstep_acks`` as ((topic, lag s or None for ``scan``), ...) from a list of
    [topic, lag] pairs or of topics (lag 0); a string is parsed as YAML first."""
    import yaml

    from slam_predict.errors import InputError

    if isinstance(value, str):
        value = yaml.safe_load(value) if value.strip() else []
    pairs = []
    for item in value or []:
        if isinstance(item, str):
            item = [item, 0.0]
        ok = isinstance(item, (list, tuple)) and len(item) == 2 and isinstance(item[0], str)
        if ok and item[1] == "scan":
            pairs.append((item[0], None))
            continue
        try:
            pairs.append((item[0], float(item[1])))
            ok = ok and pairs[-1][1] >= 0
        except (TypeError, ValueError, IndexError, KeyError):
            ok = False
        if not ok:
            raise InputError(f"~lockstep_acks: expected [topic, lag_s >= 0 or 'scan'] pairs, "
                             f"got {item!r}")
    return tuple(pairs)
