"""One exploration run with GMapping in the loop, from a World and a seed to a run record.

The closed loop (:class:`slam_predict.explore.loop.ClosedLoop`: simulator → GMapping →
navigator ← explorer) is stepped at ``interval_sim`` (10 Hz). At every step the ground-truth
pose, the odometry pose and the SLAM pose (map→odom ∘ odom→base_link, not only at processed
scans) are recorded. The stop rule (:mod:`slam_predict.collect.stopping`) snapshots the SLAM map
over its full xmin..xmax extent; when no frontier is left the robot idles and the MSE rule still
decides, as in the thesis. The sim-time cap and the wall-clock cap also end a run (the reason
is recorded); a stuck robot is recorded (run.json ``stuck``), not stopped. The record is
written into a temporary folder renamed at the end.
"""
from __future__ import annotations

import logging
import time
from pathlib import Path

import numpy as np

from slam_predict.atomic import atomic_dir
from slam_predict.collect import interrupt
from slam_predict.collect import record as rec
from slam_predict.collect.settings import CollectSettings, load_settings
from slam_predict.collect.stopping import SnapshotMSE, StuckDetector, grid_to_snapshot, stop_reason
from slam_predict.config import to_dict
from slam_predict.paths import portable_path

LOG = logging.getLogger(__name__)


def full_extent_grid(grid, extent) -> np.ndarray:
    """The SLAM grid pasted into the full canvas ``extent`` = (xmin, ymin, xmax, ymax) m (the
    back-end's ``map_extent``) at the grid's resolution (−1 fill)."""
    xmin, ymin, xmax, ymax = extent
    delta = float(grid.resolution)
    width = int(round((xmax - xmin) / delta))
    height = int(round((ymax - ymin) / delta))
    canvas = np.full((height, width), -1, dtype=np.int8)
    col0 = int(round((grid.origin[0] - xmin) / delta))
    row0 = int(round((grid.origin[1] - ymin) / delta))
    src = grid.data
    r0, c0 = max(row0, 0), max(col0, 0)
    r1, c1 = min(row0 + src.shape[0], height), min(col0 + src.shape[1], width)
    if r1 > r0 and c1 > c0:
        canvas[r0:r1, c0:c1] = src[r0 - row0:r1 - row0, c0 - col0:c1 - col0]
    return canvas


class Recorder:
    """Per-step trajectories (10 Hz) and the stuck detector."""

    def __init__(self):
        self.t: list[float] = []
        self.gt: list[np.ndarray] = []
        self.slam: list[np.ndarray] = []
        self.odom: list[np.ndarray] = []
        self.stuck = StuckDetector()

    def add(self, loop) -> None:
        state = loop.state
        self.t.append(float(state.t))
        self.gt.append(np.array(state.true_pose, float))
        self.slam.append(np.array(loop.robot_pose_map, float))
        self.odom.append(np.array(state.odom_pose, float))
        self.stuck.add(float(state.t), state.true_pose[0], state.true_pose[1],
                       not loop.explorer.done)

    def trajectories(self) -> rec.Trajectories:
        return rec.Trajectories(np.asarray(self.t), np.asarray(self.gt), np.asarray(self.slam),
                                np.asarray(self.odom))


def explore_until_stop(loop, settings: CollectSettings, folder: Path, free_area_m2: float,
                       bar=None):
    """Step ``loop`` until the stop rule (or a limit) ends the run; snapshots go to ``folder``;
    ``bar`` (a tqdm bar, or None) is moved on by every simulated second."""
    rule = SnapshotMSE(settings.stop, settings.stop.interval_for(free_area_m2))
    recorder = Recorder()
    wall_start = time.perf_counter()
    explorer_end: dict | None = None
    while True:
        interrupt.check()   # SIGINT/SIGTERM or a dead batch process: discard the run
        loop.step()
        recorder.add(loop)
        if bar is not None and loop.t >= bar.n + 1.0:
            bar.update(int(loop.t) - bar.n)
        if loop.explorer.done and explorer_end is None:
            explorer_end = {"t": loop.t, "reason": str(loop.explorer.log.stop_reason)}
        if rule.due(loop.t) and loop.grid is not None:
            snapshot = grid_to_snapshot(full_extent_grid(loop.source.map(),
                                                         loop.source.map_extent))
            rule.add(loop.t, snapshot)
            rec.write_snapshot(folder, len(rule.times), snapshot)
        reason = stop_reason(settings.stop, rule, loop.t, time.perf_counter() - wall_start)
        if reason:
            return reason, rule, recorder, explorer_end, time.perf_counter() - wall_start


def sim_time_bar(spec, max_sim_time_s: float):
    """A progress bar of the run's simulated seconds (up to the stop rule's limit), shown only
    when the batch runs its episodes in this process with progress on (``spec.options``)."""
    from tqdm import tqdm

    return tqdm(total=int(max_sim_time_s), unit="sim s", leave=False, mininterval=1.0,
                desc=f"{spec.world} run {spec.index}",
                disable=not spec.options.get("progress"))


def _sensor_recorder(folder: Path, loop, spec):
    from slam_predict.collect.sensorlog import SensorLogRecorder

    recorder = SensorLogRecorder(folder, loop.publisher, header=[
        f"slam_predict {rec.code_version()} sensor log: world {spec.world} "
        f"({portable_path(spec.world_path)}), run {spec.index}, seed {spec.seed}"])
    loop.observers.append(recorder)
    return recorder


def _finish_sensor_logs(sensors, folder: Path, loop, settings: CollectSettings) -> dict:
    """Close the sensor logs, write the in-loop SLAM trajectory; run.json's ``sensor_logs``."""
    from slam_predict.collect.sensorlog import SLAM_SCANS
    from slam_predict.config import to_dict
    from slam_predict.formats.tum import write_tum

    summary = sensors.close()
    _, times, poses = loop.source.trajectory()
    write_tum(folder / SLAM_SCANS, times, poses)
    return {**summary, "slam_scans": int(len(times)),
            settings.slam.type: to_dict(settings.slam.params)}


def swept(world, reach, truth_poses, laser, settings: CollectSettings) -> float:
    """run.json's ``coverage_swept`` (:func:`slam_predict.explore.seen.swept_coverage`)."""
    from slam_predict.explore.seen import swept_coverage, usable_range

    return swept_coverage(world, reach, truth_poses, laser,
                          usable_range(settings.slam.params, laser.range_max))


def run_episode(spec, settings: CollectSettings | None = None,
                extra: dict | None = None) -> dict:
    """Run one exploration (a :class:`~slam_predict.collect.batch.RunSpec`); returns run.json
    (with the entries of ``extra`` added, e.g. a robot design's ``design``)."""
    from slam_predict.explore.coverage import coverage, reachable_free
    from slam_predict.explore.loop import ClosedLoop
    from slam_predict.nav.costmap import inscribed_radius
    from slam_predict.world.load import load_plan

    settings = settings or load_settings(spec.options.get("settings"), spec.options.get("robot"),
                                         force_robot=bool(spec.options.get("force_robot")))
    world = load_plan(spec.world_path)
    loop = ClosedLoop(world, spec.seed, settings.nav, settings.explore, settings.sim,
                      map_source=settings.slam.type, slam_params=settings.slam.params,
                      compute=settings.compute)
    with atomic_dir(spec.out_dir) as folder:
        sensors = _sensor_recorder(folder, loop, spec) if settings.sensor_logs else None
        bar = sim_time_bar(spec, settings.stop.max_sim_time_s)
        try:
            reason, rule, recorder, explorer_end, wall = explore_until_stop(
                loop, settings, folder, world.free_area_m2, bar)
        except BaseException:
            if sensors is not None:
                sensors.abort()
            raise
        finally:
            bar.close()
        traj = recorder.trajectories()
        grid = loop.source.map()
        reach = reachable_free(world, inscribed_radius(settings.nav.global_costmap))
        info = rec.RunInfo(spec.world, spec.world_path, spec.index, spec.seed,
                           odometry_error=loop.sim.odom_error,
                           sensor=to_dict(loop.sim.sensor))
        end = rec.RunEnd(reason, explorer_end, loop.t, wall, loop.log.stalls,
                         coverage(world, grid, reach, loop.world_T_map),
                         recorder.stuck.record(settings.stop),
                         swept(world, reach, traj.ground_truth, loop.sim.sensor.laser, settings))
        record = rec.build_record(info, settings, settings.hashes(), end, traj, rule,
                                  world.free_area_m2, loop.timing,
                                  None if loop.delay is None else loop.delay.stats)
        rec.write_trajectories(folder, traj)
        rec.write_map(folder, grid.data, grid.resolution, grid.origin)
        realtime = getattr(loop.source, "stats", dict)().get("async")
        if realtime is not None:   # Karto's scan_gate async: its queue and busy counters
            record["slam_async"] = realtime
        if settings.bag:
            rec.write_bag(folder, traj)
        if sensors is not None:
            record["sensor_logs"] = _finish_sensor_logs(sensors, folder, loop, settings)
            record["timing"].update(sensor_logs=sensors.wall_s, sensor_logs_cpu=sensors.cpu_s)
        record.update(extra or {})
        rec.write_run_json(folder, record)
    metric = record["metric"]
    LOG.info("%s run %d: %s after %.0f s sim (%.0f s wall), %s", spec.world, spec.index, reason,
             loop.t, wall, f"trans {metric['trans_mean']:.3f} m" if metric else "no metric")
    return record


def run_design_episode(spec) -> dict:
    """Run one exploration of a robot-design campaign: the robot of the design's point for
    ``spec``'s world and run index (:mod:`slam_predict.collect.robot_design`) over the settings;
    run.json gets the point as ``design``."""
    from slam_predict.collect.robot_design import load_design

    design = load_design(spec.options["design"])
    point = design.run_point(spec.world, spec.index)
    settings = design.settings_for(load_settings(spec.options.get("settings")),
                                   point["config"], spec.options["design"])
    return run_episode(spec, settings, extra={"design": point})
