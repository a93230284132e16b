"""The in-process closed loop: simulator → map source → explorer → navigator, in sim time.

Each iteration advances the simulator by one ``interval_sim`` with the last command; a scan
goes to the map source (``perfect`` or a SLAM back-end such as GMapping) and to the local
costmap; a processed scan refreshes map→odom and, every ``map_update_interval`` (as
slam_gmapping publishes), the map handed to the global costmap and the explorer (a back-end
with a ``map_thread``, Karto as slam_toolbox, every interval whether or not a scan was
processed); the explorer
checks its goal; the navigator runs when its controller period is due (a controller faster than
``interval_sim`` runs once per step). Nothing sleeps; a seed fixes every random draw (one
SeedSequence spawned into simulator, explorer and SLAM generators).

:class:`ClosedLoop` is stepped by :meth:`ClosedLoop.step` (the collection episodes add their own
stop rules around it); :meth:`ClosedLoop.run` explores until the explorer stops.

A SLAM back-end receives each scan as slam_gmapping would from stage_ros' messages
(:mod:`slam_predict.formats.stage_stream`: nanosecond stamps, tf-decoded odometry, float32
LaserScan fields), decoded as a bag of those messages is read back, so a replay of the run's
sensor log gives the same SLAM trajectory. ``observers`` are called with every step's messages
(the collection's sensor-log recorder is one).
"""
from __future__ import annotations

import dataclasses
import logging
import math
import time
from collections import defaultdict
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from slam_predict.errors import InputError
from slam_predict.explore import PERFECT, map_sources
from slam_predict.explore.explorer import ExploreConfig, Explorer
from slam_predict.explore.mapsource import PerfectMap, PerfectMapConfig
from slam_predict.formats.stage_stream import StagePublisher, StepMessages
from slam_predict.geometry import compose, inverse, wrap_angle
from slam_predict.nav.config import MoveBaseConfig
from slam_predict.nav.navigator import GoalRecord, Navigator
from slam_predict.seeds import run_seeds
from slam_predict.sim import SimConfig, Simulator
from slam_predict.slam import LaserGeometry
from slam_predict.slam.compute_delay import ComputeDelayConfig, for_backend
from slam_predict.world.model import World

LOG = logging.getLogger(__name__)


class NavigatorClient:
    """The explorer's goal client over an in-process :class:`Navigator`."""

    def __init__(self, navigator: Navigator):
        self.navigator = navigator
        self.record: GoalRecord | None = None

    def send_goal(self, target, t: float) -> None:
        self.record = self.navigator.send_goal(target, t)

    def cancel(self, t: float) -> None:
        if self.record is not None and not self.record.done:
            self.navigator.cancel_goal(t)

    def status(self) -> int | None:
        return None if self.record is None else int(self.record.status)

    def plan_length(self) -> float | None:
        return None if self.record is None else self.record.plan_length


@dataclass
class LoopLog:
    """Per-step records of a run (sim time s, true poses, commands) and summary counters."""

    t: list[float] = field(default_factory=list)
    true_poses: list[np.ndarray] = field(default_factory=list)
    commands: list[tuple[float, float, float]] = field(default_factory=list)
    stalls: int = 0
    stalled_steps: int = 0
    distance_m: float = 0.0
    rotation_rad: float = 0.0


class ClosedLoop:
    """Simulator + map source + navigator + explorer for one World and seed.

    Args:
        world: the environment (its start pose is the robot's).
        seed: fixes every random draw of the run.
        nav: move_base configuration; explore: explorer configuration; sim: simulator.
        map_source: ``perfect`` or a SLAM back-end of :func:`map_sources`.
        perfect: perfect map source settings; slam_params: the SLAM back-end's parameters
            (``None`` = its defaults).
        compute: slam_gmapping's compute time (:mod:`slam_predict.slam.compute_delay`);
            None or model ``none``: every scan is handled at once, as in lockstep.
    """

    def __init__(self, world: World, seed: int, nav: MoveBaseConfig, explore: ExploreConfig,
                 sim: SimConfig, map_source: str = "perfect",
                 perfect: PerfectMapConfig | None = None, slam_params=None,
                 compute: ComputeDelayConfig | None = None):
        if map_source not in map_sources():
            raise InputError(f"unknown map source '{map_source}' (expected "
                             f"{' or '.join(map_sources())})")
        sim_ss, explore_ss, slam_ss = run_seeds(seed)
        self.world = world
        self.seed = seed
        self.map_source_name = map_source
        self.sim = Simulator(world, sim, np.random.default_rng(sim_ss))
        laser = LaserGeometry(self.sim.laser_angles, tuple(self.sim.laser_pose),
                              float(self.sim.laser.range_max))
        self._scan_truth = np.array(world.start_pose, dtype=float)
        self.publisher = StagePublisher.of(self.sim)
        self.observers: list[Callable[[StepMessages], None]] = []
        self.decoder = None
        if map_source == PERFECT:
            perfect = perfect or PerfectMapConfig()
            self.source = PerfectMap(world, laser, lambda: self._scan_truth, perfect)
            self.map_update_interval = perfect.map_update_interval
            self.world_T_map = np.zeros(3)
        else:
            from slam_predict.slam.bag_input import LiveDecoder
            self.decoder = LiveDecoder(self.publisher.laser)
            laser = self.decoder.laser
            self.source, self.map_update_interval = _make_slam(map_source, slam_params, laser,
                                                               np.random.default_rng(slam_ss))
            self.world_T_map = np.array(world.start_pose, dtype=float)
        self.delay = for_backend(compute, self.source, self.map_update_interval)
        self._map_thread = bool(getattr(self.source, "map_thread", False))
        # odom starts at the start pose: map_T_odom = map_T_world ⊕ world_T_odom
        self.map_T_odom = compose(inverse(self.world_T_map), world.start_pose)
        self.navigator = Navigator(nav)
        self.client = NavigatorClient(self.navigator)
        explore = _with_speed(explore, nav.TrajectoryPlannerROS.max_vel_x)
        self.explorer = Explorer(explore, self.client, np.random.default_rng(explore_ss))
        self.control_period = 1.0 / nav.controller_frequency
        self.grid = None
        self.log = LoopLog()
        self.timing: dict[str, float] = defaultdict(float)
        self.cmd = (0.0, 0.0)
        self.state = None
        self._last_map_t = -math.inf
        self._next_control = 0.0
        self._prev_stalled = False

    @property
    def t(self) -> float:
        """Current sim time, s."""
        return 0.0 if self.state is None else float(self.state.t)

    @property
    def robot_pose_map(self) -> np.ndarray:
        """The robot pose the navigation stack believes, map frame."""
        odom = np.zeros(3) if self.state is None else self.state.odom_pose
        return compose(self.map_T_odom, odom)

    def step(self) -> bool:
        """Advance one simulator step; returns False once the explorer has stopped."""
        tick = time.perf_counter()
        state = self.sim.step(*self.cmd)
        messages = self.publisher.messages(state)
        self.timing["sim"] += time.perf_counter() - tick
        self._record(state)
        if state.scan is not None:
            self._handle_scan(state, messages)
        for observer in self.observers:
            observer(messages)
        tick = time.perf_counter()
        self.explorer.step(state.t, self.grid, self.robot_pose_map)
        self.timing["explorer"] += time.perf_counter() - tick
        if self.explorer.done:
            self.cmd = (0.0, 0.0)
            return False
        if state.t + 1e-9 >= self._next_control:
            self._next_control = max(self._next_control + self.control_period, state.t)
            tick = time.perf_counter()
            self.cmd = self.navigator.step(state.t, state.odom_pose, self.map_T_odom,
                                           state.velocity)
            self.timing["navigator"] += time.perf_counter() - tick
            self.log.commands.append((float(state.t), self.cmd[0], self.cmd[1]))
        return True

    def _handle_scan(self, state, messages: StepMessages) -> None:
        tick = time.perf_counter()
        self._scan_truth = state.scan_true_pose
        if self.decoder is None:
            scan = (state.scan_odom_pose, state.scan, state.t)
        else:
            scan = self.decoder.scan(messages)
        if self.delay is None:
            processed, _ = self._update_slam(scan[2], scan)
            if self._map_due(state.t, processed):
                self._publish_map(state.t)
        elif self.delay.offer(scan[2], scan, self._update_slam):
            self._publish_map(state.t)
        self.timing["map_source"] += time.perf_counter() - tick
        laser = self.sim.laser
        self.navigator.add_scan(state.scan, self.sim.laser_angles, laser.range_min,
                                laser.range_max, state.scan_odom_pose, self.sim.laser_pose,
                                self.map_T_odom)

    def _map_due(self, t: float, processed: bool) -> bool:
        """Publish the map now? The first map with the first processed scan; then every
        ``map_update_interval`` s with a processed scan, or with none when the back-end's node
        republishes on a timer (``map_thread``: slam_toolbox)."""
        if self.grid is None:
            return processed
        due = t - self._last_map_t >= self.map_update_interval - 1e-9
        return due and (processed or self._map_thread)

    def _publish_map(self, t: float) -> None:
        """Publish the source's map; with a map thread every publication is a new message (a
        new object even when the map did not change: the explorer's "next map")."""
        grid = self.source.map()
        self.grid = dataclasses.replace(grid) if self._map_thread else grid
        self._last_map_t = t
        self.navigator.set_map(self.grid)

    def _update_slam(self, stamp: float, scan) -> tuple[bool, np.ndarray]:
        """The map source handles a scan (odometry pose, ranges, stamp) at once or from the
        compute delay's queue; refreshes map → odom when it was processed. (processed, ranges)"""
        odom_pose, ranges, _ = scan
        processed = self.source.update(odom_pose, ranges, stamp) is not None
        if processed:
            self.map_T_odom = np.asarray(self.source.map_to_odom(), dtype=float)
        return processed, ranges

    def _record(self, state) -> None:
        log = self.log
        if log.true_poses:
            prev = log.true_poses[-1]
            log.distance_m += float(math.hypot(*(state.true_pose[:2] - prev[:2])))
            log.rotation_rad += float(abs(wrap_angle(state.true_pose[2] - prev[2])))
        log.t.append(float(state.t))
        log.true_poses.append(np.array(state.true_pose, dtype=float))
        if state.stalled:
            log.stalled_steps += 1
            if not self._prev_stalled:
                log.stalls += 1
        self._prev_stalled = bool(state.stalled)
        self.state = state

    def run(self, max_sim_time: float) -> str:
        """Step until the explorer stops or ``max_sim_time`` s; returns the stop reason."""
        while self.t < max_sim_time:
            if not self.step():
                return str(self.explorer.log.stop_reason)
        if self.explorer.goal is not None:
            self.client.cancel(self.t)
        return "max_sim_time"


def _with_speed(cfg: ExploreConfig, max_vel_x: float) -> ExploreConfig:
    """The explorer's time limit uses the controller's max_vel_x."""
    return dataclasses.replace(cfg, max_vel_x=float(max_vel_x))


def _make_slam(name: str, params, laser: LaserGeometry, rng):
    """A SLAM back-end from the registry of :mod:`slam_predict.slam` and its map interval."""
    from slam_predict import slam
    try:
        if params is None:
            params = slam.backend_class(name).default_params()
        backend = slam.create(name, params=params, laser=laser, rng=rng)
    except ImportError as exc:
        raise InputError(f"map source '{name}' is not available ({exc})") from None
    return backend, backend.map_update_interval
