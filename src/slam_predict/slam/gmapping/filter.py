"""The Rao-Blackwellized particle filter of openslam_gmapping (gridslamprocessor), and the
:class:`GMapping` SLAM back-end that drives it the way slam_gmapping does.

Per scan (processScan): every particle is moved by the motion model; the scan is processed on
the first scan or once the accumulated odometry exceeds linearUpdate / angularUpdate, or
temporalUpdate seconds passed (if ≥ 0). Processing = scan-match every particle on its own map
(hill climbing from the sampled pose; the log-likelihood of the final pose is added to
``weight`` and ``weightSum``), normalise, and resample (systematic) when Neff < resampleThreshold·N
— resampled particles share their maps and restart with weight 0 — then register the scan's
endpoints into every particle's map. The best particle is the one with the largest weightSum.
All poses here are poses of the laser in the odom/map frames (m, rad).
"""
from __future__ import annotations

import logging

import numpy as np

from slam_predict.geometry import compose, inverse
from slam_predict.slam import LaserGeometry, OccupancyGrid, SlamBackend
from slam_predict.slam.gmapping import drand48, kernels, raytrace
from slam_predict.slam.gmapping.drand48 import noise_generator
from slam_predict.slam.gmapping.maps import Geometry, ParticleMap, PatchPool
from slam_predict.slam.gmapping.motion import draw_from_motion, travelled
from slam_predict.slam.gmapping.params import (
    GMappingParams,
    params_from_dict,
    params_from_record,
    with_ranges,
)
from slam_predict.slam.gmapping.tree import TrajectoryTree

LOG = logging.getLogger(__name__)
JUMP_WARNING = 20.0  # m of accumulated odometry without a processed scan (upstream warning)
# Initial patch-pool size: 32768 patches = 384 MiB reserved, committed only as patches are used.
POOL_CAPACITY = 32768


def normalized_weights(log_weights: np.ndarray, ogain: float):
    """GridSlamProcessor::normalize → (weights summing to 1, Neff = 1/Σw²)."""
    log_weights = np.asarray(log_weights, dtype=float)
    gain = 1.0 / (ogain * len(log_weights))
    w = np.exp(gain * (log_weights - log_weights.max()))
    w /= w.sum()
    return w, 1.0 / float(np.sum(w * w))


def systematic_resample(weights: np.ndarray, u: float) -> np.ndarray:
    """uniform_resampler::resampleIndexes with offset fraction ``u`` ∈ [0, 1): N indices.

    One target every Σw/N, starting at u·Σw/N; index i is taken once per target its cumulative
    weight passes. Slots left by round-off stay 0, as upstream.
    """
    weights = np.asarray(weights, dtype=float)
    n = len(weights)
    interval = weights.sum() / n
    targets = interval * u + interval * np.arange(n)
    cumulative = np.cumsum(weights)
    # index i is selected for every target t with cum[i-1] <= t < cum[i]  (strict: cum > t)
    idx = np.searchsorted(cumulative, targets, side="right")
    out = np.zeros(n, dtype=np.int64)
    valid = idx < n
    out[:int(valid.sum())] = idx[valid]
    return out


def centred_laser(laser: LaserGeometry):
    """slam_gmapping's "centred laser": (its pose in the base frame — the laser pose turned to the
    middle of the scan — and the beam angles relative to it, symmetric about 0)."""
    angles = np.asarray(laser.angles, dtype=float)
    centre = 0.5 * (angles[0] + angles[-1])
    pose = compose(np.asarray(laser.pose_in_base, dtype=float), np.array([0.0, 0.0, centre]))
    return pose, angles - centre


def range_sensor_angles(angles) -> np.ndarray:
    """The beam angles the slam_gmapping node gives the filter (rad, centred laser frame).

    The node builds GMapping's RangeSensor from the beam count N and |angle_increment|, whose
    constructor sets beam i to −N·inc/2 + i·inc: from −N·inc/2 to +(N/2 − 1)·inc, i.e. half a
    beam clockwise of the scan's own angles, which are symmetric about the centred frame
    (−(N−1)·inc/2 … +(N−1)·inc/2; its published map uses those). Uniform spacing is assumed,
    as in a LaserScan.
    """
    angles = np.asarray(angles, dtype=float)
    n = len(angles)
    increment = abs(angles[-1] - angles[0]) / (n - 1) if n > 1 else 0.0
    return -0.5 * increment * n + increment * np.arange(n)


def pose_entropy(log_weights: np.ndarray) -> float:
    """slam_gmapping computePoseEntropy: −Σ p log p with p = weight_i / Σ weight (raw log
    weights, as the node does); 0 when undefined."""
    w = np.asarray(log_weights, dtype=float)
    total = w.sum()
    if total == 0.0:
        return 0.0
    p = w / total
    p = p[p > 0.0]
    return float(-np.sum(p * np.log(p)))


class GridSlamProcessor:
    """The particle filter; poses are laser poses. See the module docstring."""

    def __init__(self, params: GMappingParams, angles: np.ndarray, rng: np.random.Generator):
        if params.maxRange is None or params.maxUrange is None:
            raise ValueError("maxRange/maxUrange must be resolved (params.with_ranges)")
        self.params = params
        self.rng = rng
        self.angles = np.asarray(angles, dtype=float)
        self.ca = np.cos(self.angles)
        self.sa = np.sin(self.angles)
        self.count = 0
        self.reading_count = 0
        self.neff = float(params.particles)
        self.neff_history: list[float] = []
        self.resamples = 0
        self.pool: PatchPool | None = None
        self.maps: list[ParticleMap] = []

    # ------------------------------------------------------------------ setup
    def init(self, initial_pose) -> None:
        """GridSlamProcessor::init: all particles at ``initial_pose`` on empty maps."""
        p = self.params
        n = p.particles
        self.poses = np.tile(np.asarray(initial_pose, dtype=float), (n, 1))
        self.weight = np.zeros(n)
        self.weight_sum = np.zeros(n)
        self.tree = TrajectoryTree(initial_pose, capacity=max(1024, 64 * n))
        self.nodes = np.zeros(n, dtype=np.int64)
        self.pool = PatchPool(capacity=POOL_CAPACITY)
        geometry = Geometry.particle_map(p.xmin, p.ymin, p.xmax, p.ymax, p.delta)
        first = ParticleMap(self.pool, geometry)
        self.maps = [first] + [first.clone() for _ in range(n - 1)]
        self.odo_pose = np.asarray(initial_pose, dtype=float)
        self.linear_distance = 0.0
        self.angular_distance = 0.0
        self.last_update_time = 0.0

    # ------------------------------------------------------------------ per scan
    def process_scan(self, laser_pose, ranges: np.ndarray, t: float) -> bool:
        """processScan with the laser's odometry pose; True when the scan was processed."""
        p = self.params
        laser_pose = np.asarray(laser_pose, dtype=float)
        if self.count == 0:
            self.odo_pose = laser_pose
        self.poses = draw_from_motion(self.poses, laser_pose, self.odo_pose, p.srr, p.srt,
                                      p.str, p.stt, self.rng)
        lin, ang = travelled(laser_pose, self.odo_pose)
        self.linear_distance += lin
        self.angular_distance += ang
        if self.linear_distance > JUMP_WARNING:
            LOG.warning("odometry moved %.1f m since the last processed scan: big jump",
                        self.linear_distance)
        self.odo_pose = laser_pose
        processed = (self.count == 0 or self.linear_distance >= p.linearUpdate
                     or self.angular_distance >= p.angularUpdate
                     or (p.temporalUpdate >= 0.0 and t - self.last_update_time > p.temporalUpdate))
        if processed:
            self.last_update_time = t
            ranges = np.ascontiguousarray(ranges, dtype=float)
            self._time = float(t)
            if self.count > 0:
                self._scan_match(ranges)
                _, self.neff = normalized_weights(self.weight, p.ogain)
                self.neff_history.append(self.neff)
                self._resample_and_register(ranges)
            else:
                self._register_all(ranges, self.nodes)
            _, self.neff = normalized_weights(self.weight, p.ogain)
            self.linear_distance = self.angular_distance = 0.0
            self.count += 1
        self.reading_count += 1
        return processed

    def _scan_match(self, ranges: np.ndarray) -> None:
        p = self.params
        for i, pmap in enumerate(self.maps):
            g = pmap.geometry
            x, y, th, _, lik = kernels.match_particle(
                pmap.table, g.sx2, g.sy2, g.cx, g.cy, g.delta, self.pool.acc, self.pool.hits,
                self.poses[i, 0], self.poses[i, 1], self.poses[i, 2], ranges, self.ca, self.sa,
                p.maxUrange, p.sigma, p.lsigma, p.kernelSize, p.lskip, p.reproduce_freecell_bug,
                p.lstep, p.astep, p.iterations, p.minimumScore)
            self.poses[i] = (x, y, th)
            self.weight[i] += lik
            self.weight_sum[i] += lik

    def _resample_and_register(self, ranges: np.ndarray) -> None:
        p = self.params
        n = len(self.maps)
        if self.neff < p.resampleThreshold * n:
            weights, _ = normalized_weights(self.weight, p.ogain)
            idx = systematic_resample(weights, float(self.rng.random()))
            new_maps = [self.maps[i].clone() for i in idx]
            for pmap in self.maps:
                pmap.release()
            self.maps = new_maps
            self.poses = self.poses[idx].copy()
            self.weight = np.zeros(n)
            self.weight_sum = self.weight_sum[idx].copy()
            self.resamples += 1
            self._register_all(ranges, self.nodes[idx])
        else:
            self._register_all(ranges, self.nodes)

    def _register_all(self, ranges: np.ndarray, parents: np.ndarray) -> None:
        p = self.params
        self.nodes = self.tree.add_nodes(self.poses, parents, self.count)
        self.tree.add_reading(self.count, ranges, self._time)  # after: a compaction keeps it
        for i, pmap in enumerate(self.maps):
            pmap.register(self.poses[i], ranges, self.ca, self.sa, p.maxRange, p.maxUrange)

    # ------------------------------------------------------------------ results
    @property
    def best_index(self) -> int:
        """getBestParticleIndex: the particle with the largest weightSum (first on ties)."""
        return int(np.argmax(self.weight_sum))

    def best_trajectory(self):
        """(processed-scan numbers (K,), times s (K,), laser poses (K, 3)) of the best particle,
        one node per processed scan, oldest first."""
        scans, poses = self.tree.trajectory(int(self.nodes[self.best_index]))
        t = np.array([self.tree.times[int(k)] for k in scans])
        return scans, t, poses

    def best_scans(self):
        """(laser poses (K, 3), readings (K, B)) of the best trajectory, newest first."""
        scans, poses = self.tree.trajectory(int(self.nodes[self.best_index]))
        readings = np.array([self.tree.readings[int(k)] for k in scans[::-1]])
        return poses[::-1].copy(), readings.reshape(len(scans), len(self.angles))


class GMapping(SlamBackend):
    """The ``gmapping`` SLAM back-end: slam_gmapping's use of the filter, plus the published map.

    ``laser`` gives the beam angles and the laser pose in the base frame; as slam_gmapping, the
    filter runs on a laser frame whose yaw is the centre of the scan, which is undone in every
    pose returned here. The published map uses the scan's angles made symmetric about that frame;
    the filter uses :func:`range_sensor_angles` (half a beam off) unless
    ``params.range_sensor_angles`` is False.
    """

    name = "gmapping"
    label = "GMapping"
    incremental_map = True  # False: rebuild the published map from scratch at every map()

    @classmethod
    def params_from_dict(cls, data, source: str = "<config>") -> GMappingParams:
        return params_from_dict(data, source)

    @classmethod
    def params_from_record(cls, data, source: str = "<run record>") -> GMappingParams:
        return params_from_record(data, source)

    @classmethod
    def warmup(cls) -> None:
        kernels.warmup()
        raytrace.warmup()
        drand48.warmup()

    @classmethod
    def extent_of(cls, params: GMappingParams):
        """slam_gmapping's initial map: (xmin, ymin, xmax, ymax) m."""
        return (params.xmin, params.ymin, params.xmax, params.ymax)

    def __init__(self, params: GMappingParams, laser: LaserGeometry,
                 rng: np.random.Generator | None = None):
        """``rng``: the run's numpy generator (fresh when None); the filter draws from it
        (``random_stream: numpy``) or from drand48 seeded by ``drand48_seed`` or, when that is
        None, by a number drawn from ``rng`` (see :func:`.drand48.noise_generator`)."""
        from slam_predict.slam.gmapping.gridmap import IncrementalMap, MapBuilder

        self.laser_in_base, angles = centred_laser(laser)
        self.params = with_ranges(params, laser.range_max)
        matched = range_sensor_angles(angles) if self.params.range_sensor_angles else angles
        noise, self.drand48_seed = noise_generator(
            self.params.random_stream, self.params.drand48_seed,
            rng if rng is not None else np.random.default_rng())
        self.filter = GridSlamProcessor(self.params, matched, noise)
        self._angles = angles
        self.builder = MapBuilder(self.params, angles)
        self.published = IncrementalMap(self.builder)
        self._map_to_odom = np.zeros(3)
        self._odom = np.zeros(3)
        self.last_processed = False

    @property
    def beam_angles(self) -> np.ndarray:
        """The scan's beam angles (rad) in the centred laser frame."""
        return self._angles

    def laser_pose(self, odom_pose) -> np.ndarray:
        """The (centred) laser pose in the odom frame for a robot odometry pose."""
        return compose(np.asarray(odom_pose, dtype=float), self.laser_in_base)

    def update(self, odom_pose, scan_ranges, t: float) -> np.ndarray | None:
        self._odom = np.asarray(odom_pose, dtype=float)
        laser = self.laser_pose(odom_pose)
        ranges = np.asarray(scan_ranges, dtype=float)
        if ranges.shape != self.filter.angles.shape:
            raise ValueError(f"scan has {ranges.size} ranges, the laser {self.filter.angles.size}")
        if self.filter.pool is None:
            self.filter.init(laser)
        self.last_processed = self.filter.process_scan(laser, ranges, float(t))
        if not self.last_processed:
            return None
        best = self.filter.poses[self.filter.best_index]
        self._map_to_odom = compose(best, inverse(laser))
        return self.pose()

    def pose(self) -> np.ndarray:
        """map → odom ∘ the latest odometry pose, i.e. what tf gives for map → base_link."""
        return compose(self._map_to_odom, self._odom)

    def map_to_odom(self) -> np.ndarray:
        return self._map_to_odom.copy()

    def map(self) -> OccupancyGrid:
        """The published map of the best particle's trajectory (updated incrementally from the
        previous call's; identical to :meth:`rebuilt_map`)."""
        if self.filter.pool is None:
            return self.builder.empty()
        if not self.incremental_map:
            return self.rebuilt_map()
        f = self.filter
        scans, poses = f.tree.trajectory(int(f.nodes[f.best_index]))
        return self.published.build(scans, poses, f.tree.readings.__getitem__)

    def rebuilt_map(self) -> OccupancyGrid:
        """The published map rebuilt from scratch, as slam_gmapping's updateMap does."""
        if self.filter.pool is None:
            return self.builder.empty()
        poses, readings = self.filter.best_scans()
        return self.builder.build(poses, readings)

    def trajectory(self):
        """(processed-scan numbers (K,), times s (K,), robot poses (K, 3) in the map frame):
        the best particle's trajectory, one pose per processed scan."""
        scans, t, poses = self.filter.best_trajectory()
        return scans, t, compose(poses, inverse(self.laser_in_base)).reshape(-1, 3)

    def entropy(self) -> float:
        """Pose entropy as slam_gmapping publishes it on ~entropy."""
        return pose_entropy(self.filter.weight) if self.filter.pool is not None else 0.0

    def stats(self) -> dict:
        """Run statistics: scans seen/processed, resamples, Neff summary, pool use, the random
        stream and its drand48 seed (None on the numpy stream)."""
        f = self.filter
        neff = np.array(f.neff_history) if f.neff_history else np.array([float("nan")])
        return {
            "scans_seen": f.reading_count,
            "scans_processed": f.count,
            "resamples": f.resamples,
            "particles": self.params.particles,
            "neff_mean": float(np.mean(neff)),
            "neff_min": float(np.min(neff)),
            "neff_final": float(f.neff),
            "patches_in_use": f.pool.in_use if f.pool is not None else 0,
            "patch_pool_mib": (f.pool.nbytes / 2 ** 20) if f.pool is not None else 0.0,
            "tree_nodes": f.tree.size if f.pool is not None else 0,
            "neff_history": [round(v, 3) for v in f.neff_history],
            "maxRange": self.params.maxRange,
            "maxUrange": self.params.maxUrange,
            "random_stream": self.params.random_stream,
            "drand48_seed": self.drand48_seed,
        }
