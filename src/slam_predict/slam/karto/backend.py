"""The ``karto`` SLAM back-end: slam_toolbox's scan gate, Karto's Mapper::Process (has-moved-
enough rule, sequential matching against the running scans) and the occupancy grid rebuilt from
the corrected poses (docs/karto.md)."""
from __future__ import annotations

import math

import numpy as np

from slam_predict.slam import LaserGeometry, OccupancyGrid, SlamBackend
from slam_predict.slam.karto import kernels, occupancy
from slam_predict.slam.karto.graph import MapperGraph
from slam_predict.slam.karto.matcher import ScanMatcher, SearchSettings
from slam_predict.slam.karto.params import KartoParams, params_from_dict
from slam_predict.slam.karto.realtime import AsyncMapper, CallCost
from slam_predict.slam.karto.scan import (
    TOLERANCE,
    LocalizedScan,
    RangeFinder,
    compose,
    normalize_angle,
    relative,
    transform_pose,
)


def range_finder(laser: LaserGeometry, max_laser_range: float) -> RangeFinder:
    """The LaserRangeFinder slam_toolbox builds from a scan's description."""
    angles = laser.angles
    step = (angles[-1] - angles[0]) / (len(angles) - 1) if len(angles) > 1 else 0.0
    maximum = laser.range_max if math.isfinite(laser.range_max) else max_laser_range
    return RangeFinder(tuple(laser.pose_in_base), float(angles[0]), float(step), 0.0,
                       float(maximum), float(min(max_laser_range, maximum)), len(angles))


def search_settings(p: KartoParams) -> SearchSettings:
    """The matcher's view of the parameters (Mapper's setters square the two variance
    penalties: slam_toolbox's values are standard deviations, m and rad)."""
    return SearchSettings(p.coarse_search_angle_offset, p.coarse_angle_resolution,
                          p.fine_search_angle_offset, p.distance_variance_penalty ** 2,
                          p.minimum_distance_penalty, p.angle_variance_penalty ** 2,
                          p.minimum_angle_penalty, p.use_response_expansion)


class ScanGate:
    """slam_toolbox's shouldProcessScan (sync node): the first scan passes; later ones need the
    sequence number (input index) a multiple of ``throttle_scans`` and ≥ 5, ``minimum_time_
    interval`` s since the last passed scan and squared odometric travel ≥ 0.8·d²."""

    def __init__(self, p: KartoParams):
        self.p = p
        self.last = None

    def passes(self, sequence: int, t: float, odom) -> bool:
        if self.last is None:
            self.last = (t, np.asarray(odom, float))
            return True
        if sequence % self.p.throttle_scans != 0 or t - self.last[0] < self.p.minimum_time_interval:
            return False
        moved = float(np.sum((np.asarray(odom[:2]) - self.last[1][:2]) ** 2))
        if moved < 0.8 * self.p.minimum_travel_distance ** 2 or sequence < 5:
            return False
        self.last = (t, np.asarray(odom, float))
        return True


class Mapper:
    """Karto's Mapper in mapping mode: the processed scans, the running scans and the graph."""

    def __init__(self, p: KartoParams, laser: RangeFinder):
        self.p = p
        self.laser = laser
        self.scans: list[LocalizedScan] = []
        self.running: list[LocalizedScan] = []
        self.matcher = ScanMatcher(search_settings(p), p.correlation_search_space_dimension,
                                   p.correlation_search_space_resolution,
                                   p.correlation_search_space_smear_deviation,
                                   laser.range_threshold)
        self._loop_matcher = None
        self.graph = MapperGraph(self) if p.use_scan_matching else None

    def loop_matcher(self) -> ScanMatcher:
        """The loop-closure matcher (its grid built on first use)."""
        if self._loop_matcher is None:
            p = self.p
            self._loop_matcher = ScanMatcher(search_settings(p), p.loop_search_space_dimension,
                                             p.loop_search_space_resolution,
                                             p.loop_search_space_smear_deviation,
                                             self.laser.range_threshold)
        return self._loop_matcher

    def has_moved_enough(self, scan: LocalizedScan, last: LocalizedScan | None) -> bool:
        """Mapper::HasMovedEnough on the odometric sensor poses (the time test never fires:
        slam_toolbox leaves scan times at 0)."""
        if last is None:
            return True
        before = last.sensor_at(last.odometric_pose)
        now = scan.sensor_at(scan.odometric_pose)
        if abs(normalize_angle(now[2] - before[2])) >= self.p.minimum_travel_heading:
            return True
        travel = (now[0] - before[0]) ** 2 + (now[1] - before[1]) ** 2
        return travel >= self.p.minimum_travel_distance ** 2 - TOLERANCE

    def process(self, scan: LocalizedScan) -> bool:
        """Mapper::Process: True when the scan was added."""
        last = self.scans[-1] if self.scans else None
        if last is not None:
            scan.set_corrected_pose(transform_pose(last.odometric_pose, last.corrected_pose,
                                                   scan.odometric_pose))
        if not self.has_moved_enough(scan, last):
            return False
        cov = np.eye(3)
        if self.p.use_scan_matching and last is not None:
            _, best, cov = self.matcher.match(scan, self.running)
            scan.set_sensor_pose(best)
        scan.unique_id = len(self.scans)
        self.scans.append(scan)
        if self.p.use_scan_matching:
            if self.graph is not None:
                self.graph.add(scan, cov)
            self._add_running(scan)
            if self.graph is not None and self.p.do_loop_closing:
                self.graph.try_close_loop(scan)
        return True

    def _add_running(self, scan: LocalizedScan) -> None:
        """MapperSensorManager::AddRunningScan: cap the buffer by count and by distance."""
        self.running.append(scan)
        limit = self.p.scan_buffer_maximum_scan_distance ** 2 - TOLERANCE

        def spread():
            a, b = self.running[0].sensor_pose, self.running[-1].sensor_pose
            return (a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2

        while len(self.running) > self.p.scan_buffer_size or spread() > limit:
            self.running.pop(0)


class Karto(SlamBackend):
    """Karto (slam_toolbox's karto_sdk) behind the SlamBackend interface."""

    name = "karto"
    label = "Karto"
    map_thread = True    # slam_toolbox's publishVisualizations loop

    @classmethod
    def params_from_dict(cls, data, source: str = "<config>") -> KartoParams:
        return params_from_dict(data, source)

    @classmethod
    def extent_of(cls, params: KartoParams):
        return (params.xmin, params.ymin, params.xmax, params.ymax)

    @classmethod
    def warmup(cls) -> None:
        points = np.zeros((2, 2))
        kernels.valid_points(points, 1.0, 1.0)
        occupancy.trace_line(np.zeros((2, 2), np.int64), 0, 0, 1, 1)

    def __init__(self, params: KartoParams, laser: LaserGeometry,
                 rng: np.random.Generator | None = None):
        """``rng`` is unused: Karto draws nothing at random."""
        self.params = params
        self.laser = laser
        self.mapper = Mapper(params, range_finder(laser, params.max_laser_range))
        self.gate = ScanGate(params)
        self._odom = np.zeros(3)
        self._map_to_odom = np.zeros(3)
        self._seen = 0
        self._map: OccupancyGrid | None = None
        self.realtime = (AsyncMapper(params.async_cost, params.map_update_interval,
                                     self._map_size) if params.scan_gate == "async" else None)
        self._box = None   # (xmin, ymin, xmax, ymax) m of the processed scans' points

    @property
    def beam_angles(self) -> np.ndarray:
        return self.laser.angles

    def update(self, odom_pose, scan_ranges, t: float) -> np.ndarray | None:
        self._odom = np.asarray(odom_pose, float)
        ranges = np.asarray(scan_ranges, float)
        if ranges.shape != self.laser.angles.shape:
            raise ValueError(f"scan has {ranges.size} ranges, the laser {self.laser.beams}")
        sequence, self._seen = self._seen, self._seen + 1
        if self.realtime is not None:
            added = []
            self.realtime.offer(float(t), (sequence, self._odom, ranges),
                                lambda stamp, item: self._process(*item, stamp, added))
            return self.pose() if added else None
        if self.params.scan_gate == "sync" and not self.gate.passes(sequence, float(t),
                                                                     self._odom):
            return None
        return self.pose() if self._process(sequence, self._odom, ranges, float(t)).added \
            else None

    def _process(self, sequence: int, odom: np.ndarray, ranges: np.ndarray, t: float,
                 added: list | None = None) -> CallCost:
        """Mapper::Process on one scan; on success map → odom from its corrected pose."""
        closures = self._closures()
        nodes = len(self.mapper.scans)
        scan = LocalizedScan(self.mapper.laser, sequence, t, odom, ranges)
        if not self.mapper.process(scan):
            return CallCost(False)
        self._map_to_odom = compose(scan.corrected_pose, relative(odom, np.zeros(3)))
        self._map = None
        self._grow_box(scan)
        if added is not None:
            added.append(sequence)
        return CallCost(True, self._closures() > closures, len(ranges), nodes)

    def _closures(self) -> int:
        graph = self.mapper.graph
        return 0 if graph is None else len(graph.loop_closures)

    def _grow_box(self, scan: LocalizedScan) -> None:
        low, high = scan.box_min, scan.box_max
        box = (low[0], low[1], high[0], high[1])
        self._box = box if self._box is None else (
            min(self._box[0], box[0]), min(self._box[1], box[1]),
            max(self._box[2], box[2]), max(self._box[3], box[3]))

    def _map_size(self) -> tuple[float, float]:
        """(cells of the processed scans' bounding box, beams of every processed scan): what
        a map rebuild now traces and allocates."""
        if self._box is None:
            return 0.0, 0.0
        xmin, ymin, xmax, ymax = self._box
        res = self.params.resolution
        cells = (math.floor((xmax - xmin) / res) + 1) * (math.floor((ymax - ymin) / res) + 1)
        return float(cells), float(len(self.mapper.scans) * self.laser.beams)

    def pose(self) -> np.ndarray:
        return compose(self._map_to_odom, self._odom)

    def map_to_odom(self) -> np.ndarray:
        return self._map_to_odom.copy()

    def map(self) -> OccupancyGrid:
        """OccupancyGrid::CreateFromScans of every processed scan at its corrected pose, cut to
        the canvas of :meth:`extent_of`."""
        if self._map is None:
            self._map = self._build_map()
        return self._map

    def _build_map(self) -> OccupancyGrid:
        p = self.params
        scans = self.mapper.scans
        if not scans:
            return OccupancyGrid(np.full((1, 1), -1, np.int8), p.resolution, (0.0, 0.0))
        passes, hits, offset = occupancy.counts_from_scans(scans, p.resolution)
        data = occupancy.cell_states(passes, hits, p.min_pass_through, p.occupancy_threshold)
        return cut_to_extent(data, p.resolution, offset, self.extent_of(p))

    def trajectory(self):
        scans = self.mapper.scans
        if not scans:
            return np.zeros(0, np.int64), np.zeros(0), np.zeros((0, 3))
        return (np.arange(len(scans), dtype=np.int64),
                np.array([s.time for s in scans]),
                np.array([s.corrected_pose for s in scans]))

    def stats(self) -> dict:
        graph = self.mapper.graph
        return {"scans_seen": self._seen, "scans_processed": len(self.mapper.scans),
                "accepted_input_indices": [s.input_index for s in self.mapper.scans],
                "loop_closures": [] if graph is None else list(graph.loop_closures),
                **({"async": dict(self.realtime.stats)} if self.realtime is not None else {})}


def cut_to_extent(data, resolution, offset, extent) -> OccupancyGrid:
    """The cells of ``data`` (origin ``offset``) that lie inside ``extent`` (xmin, ymin, xmax,
    ymax) m."""
    xmin, ymin, xmax, ymax = extent
    first_col = max(0, int(math.ceil((xmin - offset[0]) / resolution - 1e-9)))
    first_row = max(0, int(math.ceil((ymin - offset[1]) / resolution - 1e-9)))
    last_col = min(data.shape[1], int(math.floor((xmax - offset[0]) / resolution + 1e-9)))
    last_row = min(data.shape[0], int(math.floor((ymax - offset[1]) / resolution + 1e-9)))
    if last_col <= first_col or last_row <= first_row:
        return OccupancyGrid(np.full((1, 1), -1, np.int8), resolution, (xmin, ymin))
    origin = (offset[0] + first_col * resolution, offset[1] + first_row * resolution)
    return OccupancyGrid(data[first_row:last_row, first_col:last_col].copy(), resolution, origin)
