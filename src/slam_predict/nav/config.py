"""Typed configuration of the navigation stack, with the parameter names of move_base,
costmap_2d, navfn / global_planner and base_local_planner (ros_interfaces.md §3).

Defaults are the ROS defaults (the *effective* ones: base_local_planner's .cfg values, which the
first dynamic-reconfigure call applies over the code defaults). The project's thesis values
live in ``config/*.yaml`` and are loaded with :func:`load_nav_config`, which merges the files
the way a move_base launch file does::

    move_base.yaml            -> /move_base (controller_frequency, planner_patience, ...)
    costmap_common.yaml       -> /move_base/global_costmap and /move_base/local_costmap
    global_costmap.yaml       -> /move_base (top-level key ``global_costmap``)
    local_costmap.yaml        -> /move_base (top-level key ``local_costmap``)
    base_local_planner.yaml   -> /move_base (top-level key ``TrajectoryPlannerROS``)

so the same files work with ``<rosparam command="load">`` and in-process.

Deviations (documented in docs/architecture.md): costmaps take the pre-hydro flat parameters
(``static_map``, ``obstacle_range``, ...; one laser observation source); ``holonomic_robot`` is
false by default (the simulated robot is differential drive); recovery behaviours are listed as
``{name, type, reset_distance, layer_names}`` mappings; ``smooth_cmd_vel`` (an extension,
default on) clamps each published command to the previous one ± acc_lim·Δt, the acceleration
the rollouts already assume, so commands respect the acceleration limits.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Any, ClassVar

from slam_predict.config import (
    AT_LEAST_ONE,
    NON_NEGATIVE,
    POSITIVE,
    Range,
    check_keys,
    from_dict,
    load_yaml,
)
from slam_predict.errors import InputError

GLOBAL_PLANNERS = ("navfn/NavfnROS", "global_planner/GlobalPlanner")
LOCAL_PLANNERS = ("base_local_planner/TrajectoryPlannerROS",)
RECOVERY_TYPES = ("clear_costmap_recovery/ClearCostmapRecovery", "rotate_recovery/RotateRecovery",
                  "slam_predict/BackUpRecovery")


@dataclass
class CostmapConfig:
    """One costmap_2d instance (Costmap2DROS + static, obstacle and inflation layers).

    Units: m, Hz, s. ``footprint`` is a polygon in the robot frame; when empty the robot is a
    circle of ``robot_radius`` (costmap_2d makes a 16-gon of it).
    """

    global_frame: str = "map"
    robot_base_frame: str = "base_link"
    update_frequency: float = 5.0
    publish_frequency: float = 0.0
    transform_tolerance: float = 0.3
    width: float = 10.0
    height: float = 10.0
    resolution: float = 0.05
    origin_x: float = 0.0
    origin_y: float = 0.0
    rolling_window: bool = False
    static_map: bool = True
    track_unknown_space: bool = False
    footprint: tuple[tuple[float, float], ...] = ()
    robot_radius: float = 0.46
    footprint_padding: float = 0.01
    footprint_clearing_enabled: bool = True
    # static layer
    lethal_cost_threshold: int = 100
    unknown_cost_value: int = -1
    trinary_costmap: bool = True
    # obstacle layer (one laser source named by observation_sources; "" = no obstacle layer)
    observation_sources: str = "scan"
    marking: bool = True
    clearing: bool = False
    obstacle_range: float = 2.5
    raytrace_range: float = 3.0
    max_obstacle_height: float = 2.0
    # inflation layer
    inflation_radius: float = 0.55
    cost_scaling_factor: float = 10.0
    inflate_unknown: bool = False
    RANGES: ClassVar[dict[str, Range]] = {
        "update_frequency": NON_NEGATIVE, "publish_frequency": NON_NEGATIVE,
        "transform_tolerance": NON_NEGATIVE, "width": NON_NEGATIVE, "height": NON_NEGATIVE,
        "resolution": POSITIVE, "robot_radius": NON_NEGATIVE,
        "lethal_cost_threshold": Range(0.0, 255.0), "unknown_cost_value": Range(-1.0, 255.0),
        "obstacle_range": NON_NEGATIVE, "raytrace_range": NON_NEGATIVE,
        "max_obstacle_height": NON_NEGATIVE, "inflation_radius": NON_NEGATIVE,
        "cost_scaling_factor": NON_NEGATIVE}

    def __post_init__(self) -> None:
        if not self.resolution > 0:
            raise ValueError("resolution must be > 0")
        if self.rolling_window and not (self.width > 0 and self.height > 0):
            raise ValueError("a rolling window needs width and height > 0")
        if self.update_frequency < 0 or self.inflation_radius < 0:
            raise ValueError("update_frequency and inflation_radius must be >= 0")
        if self.footprint and len(self.footprint) < 3:
            raise ValueError("footprint needs at least 3 points")


@dataclass
class NavfnConfig:
    """navfn/NavfnROS parameters (m). ``default_tolerance``: how far from an unreachable goal
    the plan may end (the reachable cell nearest the goal within ±tolerance)."""

    allow_unknown: bool = True
    default_tolerance: float = 0.0
    planner_window_x: float = 0.0
    planner_window_y: float = 0.0
    visualize_potential: bool = False
    RANGES: ClassVar[dict[str, Range]] = {
        "default_tolerance": NON_NEGATIVE, "planner_window_x": NON_NEGATIVE,
        "planner_window_y": NON_NEGATIVE}


@dataclass
class GlobalPlannerConfig:
    """global_planner/GlobalPlanner parameters. The search is always an exact 8-connected grid
    search (``use_dijkstra`` picks Dijkstra vs A*; both return the optimal path)."""

    allow_unknown: bool = True
    default_tolerance: float = 0.0
    use_dijkstra: bool = True
    use_quadratic: bool = True
    use_grid_path: bool = False
    old_navfn_behavior: bool = False
    lethal_cost: int = 253
    neutral_cost: int = 50
    cost_factor: float = 3.0
    outline_map: bool = True
    visualize_potential: bool = False
    RANGES: ClassVar[dict[str, Range]] = {
        "default_tolerance": NON_NEGATIVE, "lethal_cost": Range(1.0, 255.0),
        "neutral_cost": Range(0.0, 253.0), "cost_factor": NON_NEGATIVE}


@dataclass
class TrajectoryPlannerConfig:
    """base_local_planner/TrajectoryPlannerROS parameters (m, s, rad, m/s, rad/s, m/s², rad/s²).

    ``meter_scoring`` multiplies path_distance_bias and goal_distance_bias by the costmap
    resolution (noetic); ``meter_scoring_occdist`` (an extension) also multiplies occdist_scale,
    as earlier base_local_planner releases did in their reconfigure callback.
    ``reverse_when_blocked`` (an extension; default off = base_local_planner): when no in-place
    rotation wins and every legal forward sample scores worse than standing still, legal
    backward arcs at ``escape_vel`` m/s (vθ over the window) are taken while they score better
    than standing still, and for at least escape_reset_dist m once begun (a multi-point turn).
    A reverse that stops short of escape_reset_dist (a wall behind) is not taken up again
    until the heading has turned escape_reset_theta rad: the robot drives forward, as
    base_local_planner does, until it can turn.
    Neither base_local_planner nor move_base's recoveries do this: base_local_planner backs up
    (straight, escape_vel) only when *no* sample is legal, until escape_reset_dist /
    escape_reset_theta; move_base's recoveries only clear costmaps and rotate in place (a
    back-up recovery exists in navigation2, not in move_base).
    ``escape_footprint_margin`` (m; an extension, 0 = base_local_planner): when nothing is
    legal and the straight escape would also collide, the planner backs up blind, as the
    original, only if no better move exists for the footprint shrunk by this margin (roughly the
    robot's body): a backward arc at ``escape_vel`` the shrunk footprint rolls out clear is
    taken instead, or, when none is (backed into a wall), such a forward arc at −``escape_vel``.
    A cycle that starts with the footprint touching an obstacle the shrunk one clears scores its
    samples (and the stop and rotation at the goal) with the shrunk footprint. A move the shrunk
    footprint chose is kept until escape_reset_dist / escape_reset_theta.
    ``escape_alternate`` (an extension; off = base_local_planner): a blind escape (its straight
    path collides in the costmap) that follows a blind escape with no legal command between
    drives straight forward at −``escape_vel`` instead, and the next such one back again: Stage
    refuses a move into a wall while its odometry integrates it, so upstream's repeated blind
    escape holds a robot whose corner touches a wall behind it for good.
    ``upstream_rules`` (off: the rules before 2026-12-07): five rules as noetic-devel has them
    (docs/architecture.md "Where our navigation differs", bench/bench_nav_diff.py)."""

    acc_lim_x: float = 2.5
    acc_lim_y: float = 2.5
    acc_lim_theta: float = 3.2
    max_vel_x: float = 0.55
    min_vel_x: float = 0.0
    max_vel_theta: float = 1.0
    min_vel_theta: float = -1.0
    min_in_place_vel_theta: float = 0.4
    escape_vel: float = -0.1
    sim_time: float = 1.7
    sim_granularity: float = 0.025
    angular_sim_granularity: float = 0.025
    vx_samples: int = 20
    vtheta_samples: int = 20
    path_distance_bias: float = 0.6
    goal_distance_bias: float = 0.8
    occdist_scale: float = 0.01
    heading_lookahead: float = 0.325
    oscillation_reset_dist: float = 0.05
    escape_reset_dist: float = 0.10
    escape_reset_theta: float = math.pi / 2.0
    reverse_when_blocked: bool = False
    escape_footprint_margin: float = 0.0
    escape_alternate: bool = False
    upstream_rules: bool = False
    holonomic_robot: bool = False
    y_vels: tuple[float, ...] = (-0.3, -0.1, 0.1, 0.3)
    dwa: bool = False
    heading_scoring: bool = False
    heading_scoring_timestep: float = 0.8
    simple_attractor: bool = False
    meter_scoring: bool = False
    meter_scoring_occdist: bool = False
    xy_goal_tolerance: float = 0.10
    yaw_goal_tolerance: float = 0.05
    latch_xy_goal_tolerance: bool = False
    prune_plan: bool = True
    trans_stopped_velocity: float = 0.01
    rot_stopped_velocity: float = 0.01
    RANGES: ClassVar[dict[str, Range]] = {
        "acc_lim_x": NON_NEGATIVE, "acc_lim_y": NON_NEGATIVE, "acc_lim_theta": NON_NEGATIVE,
        "max_vel_x": NON_NEGATIVE, "min_vel_x": NON_NEGATIVE,
        "min_in_place_vel_theta": NON_NEGATIVE, "sim_time": POSITIVE, "sim_granularity": POSITIVE,
        "angular_sim_granularity": POSITIVE, "vx_samples": AT_LEAST_ONE,
        "vtheta_samples": AT_LEAST_ONE, "path_distance_bias": NON_NEGATIVE,
        "goal_distance_bias": NON_NEGATIVE, "occdist_scale": NON_NEGATIVE,
        "heading_lookahead": NON_NEGATIVE, "oscillation_reset_dist": NON_NEGATIVE,
        "escape_reset_dist": NON_NEGATIVE, "escape_reset_theta": NON_NEGATIVE,
        "escape_footprint_margin": NON_NEGATIVE, "heading_scoring_timestep": NON_NEGATIVE,
        "xy_goal_tolerance": NON_NEGATIVE, "yaw_goal_tolerance": NON_NEGATIVE,
        "trans_stopped_velocity": NON_NEGATIVE, "rot_stopped_velocity": NON_NEGATIVE}
    HASH_OMIT_IF: ClassVar[dict[str, Any]] = {"escape_alternate": False, "upstream_rules": False}

    def __post_init__(self) -> None:
        if self.holonomic_robot:
            raise ValueError("holonomic_robot: true is not supported (the simulated robot is "
                             "differential drive)")
        if self.heading_scoring or self.simple_attractor:
            raise ValueError("heading_scoring and simple_attractor are not supported")
        if self.vx_samples < 1 or self.vtheta_samples < 1:
            raise ValueError("vx_samples and vtheta_samples must be >= 1")
        if not (self.sim_time > 0 and self.sim_granularity > 0
                and self.angular_sim_granularity > 0):
            raise ValueError("sim_time and the granularities must be > 0")
        if self.escape_footprint_margin < 0:
            raise ValueError("escape_footprint_margin must be >= 0")


@dataclass
class RecoveryBehaviorConfig:
    """One entry of move_base's ``recovery_behaviors`` list, with its own parameters.
    ``backup_dist`` (m), ``backup_speed`` (m/s), ``time_allowance`` (s) and
    ``simulate_ahead_time`` (s; 0: blind) are those of the ``slam_predict/BackUpRecovery`` type
    (an extension, after Nav2's BackUp behaviour)."""

    name: str = "conservative_reset"
    type: str = "clear_costmap_recovery/ClearCostmapRecovery"
    reset_distance: float = 3.0
    layer_names: tuple[str, ...] = ("obstacles",)
    affected_maps: str = "both"
    invert_area_to_clear: bool = False
    backup_dist: float = 0.5
    backup_speed: float = 0.15
    time_allowance: float = 10.0
    simulate_ahead_time: float = 0.0
    RANGES: ClassVar[dict[str, Range]] = {"reset_distance": NON_NEGATIVE,
                                          "backup_dist": NON_NEGATIVE,
                                          "backup_speed": POSITIVE,
                                          "time_allowance": POSITIVE,
                                          "simulate_ahead_time": NON_NEGATIVE}
    # added after campaigns were collected: at these values they keep those configs' hashes
    HASH_OMIT_IF: ClassVar[dict[str, Any]] = {"backup_dist": 0.5, "backup_speed": 0.15,
                                              "time_allowance": 10.0,
                                              "simulate_ahead_time": 0.0}

    def __post_init__(self) -> None:
        if self.type not in RECOVERY_TYPES:
            raise ValueError(f"recovery type must be one of {', '.join(RECOVERY_TYPES)}, "
                             f"got '{self.type}'")
        if self.affected_maps not in ("local", "global", "both"):
            raise ValueError("affected_maps must be local, global or both")


def _default_recoveries() -> tuple[RecoveryBehaviorConfig, ...]:
    clear = "clear_costmap_recovery/ClearCostmapRecovery"
    rotate = "rotate_recovery/RotateRecovery"
    return (RecoveryBehaviorConfig("conservative_reset", clear, 3.0),
            RecoveryBehaviorConfig("rotate_recovery", rotate),
            RecoveryBehaviorConfig("aggressive_reset", clear, 4 * 0.46),
            RecoveryBehaviorConfig("rotate_recovery", rotate))


def _local_defaults() -> CostmapConfig:
    return CostmapConfig(global_frame="odom", rolling_window=True, static_map=False, width=6.0,
                         height=6.0)


@dataclass
class MoveBaseConfig:
    """move_base parameters, with its costmaps and planners as nested sections."""

    base_global_planner: str = "navfn/NavfnROS"
    base_local_planner: str = "base_local_planner/TrajectoryPlannerROS"
    controller_frequency: float = 20.0
    planner_frequency: float = 0.0
    controller_patience: float = 15.0
    planner_patience: float = 5.0
    max_planning_retries: int = -1
    oscillation_timeout: float = 0.0
    oscillation_distance: float = 0.5
    conservative_reset_dist: float = 3.0
    clearing_rotation_allowed: bool = True
    recovery_behavior_enabled: bool = True
    shutdown_costmaps: bool = False
    smooth_cmd_vel: bool = True
    recovery_behaviors: tuple[RecoveryBehaviorConfig, ...] = field(
        default_factory=_default_recoveries)
    oscillation_recovery_behaviors: tuple[RecoveryBehaviorConfig, ...] | None = None
    oscillation_across_goals: bool = False
    global_costmap: CostmapConfig = field(default_factory=CostmapConfig)
    local_costmap: CostmapConfig = field(default_factory=_local_defaults)
    NavfnROS: NavfnConfig = field(default_factory=NavfnConfig)
    GlobalPlanner: GlobalPlannerConfig = field(default_factory=GlobalPlannerConfig)
    TrajectoryPlannerROS: TrajectoryPlannerConfig = field(default_factory=TrajectoryPlannerConfig)
    RANGES: ClassVar[dict[str, Range]] = {
        "controller_frequency": POSITIVE, "planner_frequency": NON_NEGATIVE,
        "controller_patience": NON_NEGATIVE, "planner_patience": NON_NEGATIVE,
        "max_planning_retries": Range(-1.0), "oscillation_timeout": NON_NEGATIVE,
        "oscillation_distance": NON_NEGATIVE, "conservative_reset_dist": NON_NEGATIVE}
    HASH_OMIT_IF: ClassVar[dict[str, Any]] = {"oscillation_recovery_behaviors": None,
                                              "oscillation_across_goals": False}

    def __post_init__(self) -> None:
        if self.base_global_planner not in GLOBAL_PLANNERS:
            raise ValueError(f"base_global_planner must be one of {', '.join(GLOBAL_PLANNERS)}")
        if self.base_local_planner not in LOCAL_PLANNERS:
            raise ValueError(f"base_local_planner must be one of {', '.join(LOCAL_PLANNERS)}")
        if not self.controller_frequency > 0:
            raise ValueError("controller_frequency must be > 0")
        if self.planner_frequency < 0:
            raise ValueError("planner_frequency must be >= 0")

    @property
    def sim_period(self) -> float:
        """The controller period, s (base_local_planner's sim_period)."""
        return 1.0 / self.controller_frequency


# The files of a move_base launch and where their content goes in the parameter tree.
NAV_FILES = ("move_base.yaml", "costmap_common.yaml", "global_costmap.yaml",
             "local_costmap.yaml", "base_local_planner.yaml")


def merge_nav_files(config_dir: os.PathLike | str) -> dict[str, Any]:
    """The /move_base parameter tree built from the five YAML files in ``config_dir``.

    Missing files are skipped (ROS defaults apply); costmap_common.yaml is loaded into both
    costmaps before their own files, as ``<rosparam ns="global_costmap">`` does.
    """
    config_dir = os.fspath(config_dir)

    def read(name: str, cls: type = MoveBaseConfig, section: str = "") -> dict[str, Any]:
        """The file's mapping (its ``section`` when given), checked alone so that an unknown
        key or a bad value is reported in the file that holds it."""
        path = os.path.join(config_dir, name)
        data = load_yaml(path) if os.path.exists(path) else {}
        if section:
            check_keys(data, [section], path)
            data = data.get(section) or {}
        from_dict(cls, data, path, section)
        return data

    tree: dict[str, Any] = dict(read("move_base.yaml"))
    common = read("costmap_common.yaml", CostmapConfig)
    for name in ("global_costmap", "local_costmap"):
        own = read(f"{name}.yaml", CostmapConfig, name)
        tree[name] = {**common, **tree.get(name, {}), **own}
    planner = read("base_local_planner.yaml")
    for key, value in planner.items():
        tree[key] = {**tree.get(key, {}), **value} if isinstance(value, dict) else value
    return tree


def load_nav_config(config_dir: os.PathLike | str,
                    overrides: dict[str, Any] | None = None) -> MoveBaseConfig:
    """A :class:`MoveBaseConfig` from the move_base YAML files in ``config_dir``.

    ``overrides`` (a partial tree) is merged last, one level deep per section.
    """
    tree = merge_nav_files(config_dir)
    for key, value in (overrides or {}).items():
        if isinstance(value, dict) and isinstance(tree.get(key), dict):
            tree[key] = {**tree[key], **value}
        else:
            tree[key] = value
    source = os.path.join(os.fspath(config_dir), "move_base.yaml")
    try:
        return from_dict(MoveBaseConfig, tree, source)
    except InputError:
        raise
    except (TypeError, ValueError) as exc:  # pragma: no cover - from_dict wraps these
        raise InputError(str(exc), source) from None
