"""Sensor logs of a collected run (collect.yaml ``sensor_logs: true``), written while it runs.

- ``sensors.bag``: stage_ros' stream, every step (:mod:`slam_predict.formats.sensor_bag`).
- ``sensors.log.gz``: CARMEN. ``PARAM`` lines (laser mounting, range), then per step an
  ``ODOM`` line and, when a scan was taken, a ``ROBOTLASER1`` line (every scan the simulator
  produced): ranges as float32 text, laser_x/y/theta = the ground-truth robot pose (world frame,
  the reference trajectory ``slam run`` evaluates against), robot_x/y/theta = the odometry pose
  as slam_gmapping receives it from tf, laser_tv/rv = the executed velocity, timestamps = the
  messages' stamps.
- ``slam_scans.tum``: the in-loop GMapping's final best-particle trajectory (robot pose in the
  map frame at each processed scan), what a replay of either log reproduces exactly.

Both logs are streamed to temporary names and renamed when the run ends.
"""
from __future__ import annotations

import time
from collections.abc import Iterable
from pathlib import Path

from slam_predict.formats.carmen import CarmenLogWriter, LaserScan, odom_line, param_line, scan_line
from slam_predict.formats.sensor_bag import SensorBagWriter
from slam_predict.formats.stage_stream import StepMessages

SENSOR_BAG, SENSOR_LOG, SLAM_SCANS = "sensors.bag", "sensors.log.gz", "slam_scans.tum"
# How `slam run` rebuilds the in-loop SLAM generator from run.json's seed (see explore.loop).
SLAM_RNG_RULE = "numpy.random.SeedSequence(seed).spawn(3)[2]"


class SensorLogRecorder:
    """A :class:`~slam_predict.explore.loop.ClosedLoop` observer writing ``sensors.bag`` and
    ``sensors.log.gz`` into ``folder``."""

    def __init__(self, folder: Path, publisher, header: Iterable[str] = ()):
        from slam_predict.slam.bag_input import LiveDecoder

        self.folder = Path(folder)
        self.laser = publisher.laser
        self.decoder = LiveDecoder(self.laser)
        self.scans = 0
        self.steps = 0
        self.wall_s = 0.0
        self.cpu_s = 0.0
        self.bag = SensorBagWriter(self.folder / SENSOR_BAG, self.laser)
        try:
            self.log = CarmenLogWriter(self.folder / SENSOR_LOG, header)
        except BaseException:
            self.bag.abort()
            raise
        geometry = self.decoder.laser
        for name, value in (("robot_frontlaser_offset", geometry.pose_in_base[0]),
                            ("robot_frontlaser_side_offset", geometry.pose_in_base[1]),
                            ("robot_front_laser_max", self.laser.range_max)):
            self.log.write(param_line(name, repr(float(value))))

    def __call__(self, step: StepMessages) -> None:
        tick, cpu = time.perf_counter(), time.process_time()
        self.bag.write(step)
        odom = self.decoder.odometry(step)
        v, _, w = step.odom_twist
        self.log.write(odom_line(step.t, odom, v, w))
        if step.ranges is not None:
            self.log.write(scan_line(self._carmen_scan(step, odom), range_decimals=None))
            self.scans += 1
        self.steps += 1
        self.wall_s += time.perf_counter() - tick
        self.cpu_s += time.process_time() - cpu

    def _carmen_scan(self, step: StepMessages, odom) -> LaserScan:
        geometry = self.decoder.laser
        if self.decoder.reverse:
            raise ValueError("a clockwise laser cannot be written as ROBOTLASER1 as received")
        return LaserScan(
            timestamp=step.t, ranges=step.ranges, start_angle=float(geometry.angles[0]),
            angular_resolution=self.laser.angle_increment, max_range=self.laser.range_max,
            pose=step.true_pose, odom_pose=odom, kind="ROBOTLASER1",
            fov=self.laser.angle_increment * (self.laser.beams - 1),
            tv=step.odom_twist[0], rv=step.odom_twist[2])

    def close(self) -> dict:
        """Finish both logs; returns their summary for run.json."""
        tick, cpu = time.perf_counter(), time.process_time()
        self.bag.close()
        self.log.close()
        self.wall_s += time.perf_counter() - tick
        self.cpu_s += time.process_time() - cpu
        files = {name: (self.folder / name).stat().st_size for name in (SENSOR_BAG, SENSOR_LOG)}
        return {"files": files, "steps": self.steps, "scans": self.scans,
                "slam_rng": SLAM_RNG_RULE}

    def abort(self) -> None:
        """Drop both partial logs."""
        self.bag.abort()
        self.log.abort()
