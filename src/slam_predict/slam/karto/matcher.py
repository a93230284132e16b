"""Karto's correlative scan matcher (ScanMatcher::MatchScan): a smeared correlation grid of the
base scans around the scan's sensor pose, a coarse then a fine search over x, y and heading,
the best-response pose averaged, and its covariance (m², rad²)."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from slam_predict.slam.karto import kernels
from slam_predict.slam.karto.scan import TOLERANCE, LocalizedScan, normalize_angle, relative

MAX_VARIANCE = 500.0
EXPANSION_STEP = math.radians(20.0)   # use_response_expansion: +20° per retry, 3 retries


@dataclass(frozen=True)
class SearchSettings:
    """The Mapper parameters the matcher reads (rad, m², rad²)."""

    coarse_search_angle_offset: float
    coarse_angle_resolution: float
    fine_search_angle_offset: float
    distance_variance_penalty: float
    minimum_distance_penalty: float
    angle_variance_penalty: float
    minimum_angle_penalty: float
    use_response_expansion: bool

    @property
    def penalty(self) -> np.ndarray:
        return np.array([self.distance_variance_penalty, self.minimum_distance_penalty,
                         self.angle_variance_penalty, self.minimum_angle_penalty])


def smear_kernel(smear_deviation: float, resolution: float) -> np.ndarray:
    """CorrelationGrid::CalculateKernel: round(100·exp(−d²/2σ²)) on a (2h+1)² window, h =
    round(2σ/resolution)."""
    half = int(math.floor(2.0 * smear_deviation / resolution + 0.5))
    steps = np.arange(-half, half + 1) * resolution
    distance = np.hypot(steps[None, :], steps[:, None])
    z = np.exp(-0.5 * (distance / smear_deviation) ** 2)
    return np.floor(z * kernels.OCCUPIED + 0.5).astype(np.uint8)


def angle_near(angle: float, reference: float) -> float:
    """Karto's NormalizeAngleDifference: ``angle`` moved by whole turns to within π of
    ``reference`` (rad)."""
    while angle - reference < -math.pi:
        angle += 2.0 * math.pi
    while angle - reference > math.pi:
        angle -= 2.0 * math.pi
    return angle


def average_best_pose(responses, best, center, xs, ys, angles) -> np.ndarray:
    """CorrelateScan's average of the poses whose response equals the best (within Karto's
    DoubleEqual), summed in its order and arithmetic: positions centre + step, headings by
    their mean cosine and sine."""
    iy, ix, ia = np.nonzero(np.abs(responses - best) <= TOLERANCE)
    sum_x = sum_y = theta_x = theta_y = 0.0
    for y, x, a in zip(iy.tolist(), ix.tolist(), ia.tolist(), strict=True):
        sum_x += center[0] + xs[x]
        sum_y += center[1] + ys[y]
        heading = normalize_angle(float(angles[a]))
        theta_x += math.cos(heading)
        theta_y += math.sin(heading)
    count = len(iy)
    return np.array([sum_x / count, sum_y / count, math.atan2(theta_y / count, theta_x / count)])


def search_steps(offset: float, resolution: float) -> np.ndarray:
    """The n = round(2·offset/resolution) + 1 offsets −offset + k·resolution."""
    count = int(math.floor(offset * 2.0 / resolution + 0.5)) + 1
    return -offset + np.arange(count) * resolution


class ScanMatcher:
    """One correlation grid (search side ``search_size`` m at ``resolution`` m, padded by the
    range threshold and the kernel) and its search-space probability grid."""

    def __init__(self, settings: SearchSettings, search_size: float, resolution: float,
                 smear_deviation: float, range_threshold: float):
        self.settings = settings
        self.resolution = resolution
        self.side = int(math.floor(search_size / resolution + 0.5)) + 1
        margin = int(math.ceil(range_threshold / resolution))
        size = self.side + 2 * margin
        self.kernel = smear_kernel(smear_deviation, resolution)
        border = self.kernel.shape[0] // 2
        width = size + 2 * border
        self.width_step = (width + 7) // 8 * 8
        self.roi = np.array([border, border, size, size], np.int64)
        self.grid = np.zeros(self.width_step * width, np.uint8)
        self.offset = np.zeros(2)
        self.probs = np.zeros((self.side, self.side))
        self.probs_offset = np.zeros(2)

    def match(self, scan: LocalizedScan, base_scans, penalize=True, refine=True):
        """(response in [0, 1], best sensor pose, covariance 3×3) of ``scan`` against
        ``base_scans`` (ScanMatcher::MatchScan)."""
        s = self.settings
        center = scan.sensor_pose
        if len(scan.ranges) == 0:
            return 0.0, center, np.diag([MAX_VARIANCE, MAX_VARIANCE,
                                         4.0 * s.coarse_angle_resolution ** 2])
        half_extent = 0.5 * (self.roi[2] - 1) * self.resolution
        self.offset = center[:2] - half_extent
        self._fill(base_scans, center)
        coarse_offset = 0.5 * (self.side - 1) * self.resolution
        coarse_res = 2.0 * self.resolution
        response, mean, cov = self._correlate(scan, center, coarse_offset, coarse_res,
                                              s.coarse_search_angle_offset,
                                              s.coarse_angle_resolution, penalize, False)
        if s.use_response_expansion and abs(response) < TOLERANCE:
            angle_offset = s.coarse_search_angle_offset
            for _ in range(3):
                angle_offset += EXPANSION_STEP
                response, mean, cov = self._correlate(scan, center, coarse_offset, coarse_res,
                                                      angle_offset, s.coarse_angle_resolution,
                                                      penalize, False)
                if abs(response) >= TOLERANCE:
                    break
        if refine:
            response, mean, cov = self._correlate(scan, mean, 0.5 * coarse_res, self.resolution,
                                                  0.5 * s.coarse_angle_resolution,
                                                  s.fine_search_angle_offset, penalize, True,
                                                  cov)
        return response, mean, cov

    def _fill(self, base_scans, view) -> None:
        self.grid[:] = 0
        for base in base_scans:
            keep = kernels.valid_points(base.points, float(view[0]), float(view[1]))
            kernels.add_points(self.grid, self.width_step, self.roi, base.points[keep],
                               self.offset[0], self.offset[1], self.resolution, self.kernel)

    def _offsets(self, scan, angles):
        sensor = scan.sensor_pose
        local = np.array([relative(sensor, (px, py, 0.0))[:2] for px, py in scan.points]) \
            if len(scan.points) else np.zeros((0, 2))
        local = np.where(np.isfinite(local), local, 0.0)
        return kernels.lookup_offsets(local, scan.finite, angles, self.offset[0], self.offset[1],
                                      self.resolution, self.width_step)

    def _correlate(self, scan, center, space_offset, space_res, angle_offset, angle_res,
                   penalize, fine, cov=None):
        """ScanMatcher::CorrelateScan: (best response ≤ 1, averaged pose, covariance)."""
        center = np.array(center, float)
        angles = center[2] - angle_offset + np.arange(
            int(math.floor(angle_offset * 2.0 / angle_res + 0.5)) + 1) * angle_res
        offsets = self._offsets(scan, angles)
        xs = search_steps(space_offset, space_res[0] if np.ndim(space_res) else space_res)
        ys = xs.copy()
        responses = kernels.correlate(self.grid, self.width_step, self.roi, self.offset[0],
                                      self.offset[1], self.resolution, offsets, center, xs, ys,
                                      angles, penalize, self.settings.penalty)
        best = float(responses.max())
        if not fine:
            self._store_probs(center, space_offset, xs, ys, responses)
        mean = average_best_pose(responses, best, center, xs, ys, angles)
        if fine:
            cov = cov.copy()
            cov[2, 2] = self._angular_variance(mean, best, center, angles, offsets, angle_res)
        else:
            cov = self._positional_covariance(mean, best, center, xs, ys, space_res, angle_res)
        return min(best, 1.0), mean, cov

    def _store_probs(self, center, space_offset, xs, ys, responses) -> None:
        self.probs[:] = 0.0
        self.probs_offset = center[:2] - space_offset
        for iy, y in enumerate(ys):
            gy = kernels.to_grid(center[1] + y, self.probs_offset[1], self.resolution)
            for ix, x in enumerate(xs):
                gx = kernels.to_grid(center[0] + x, self.probs_offset[0], self.resolution)
                self.probs[gy, gx] = max(self.probs[gy, gx], responses[iy, ix].max())

    def _positional_covariance(self, mean, best, center, xs, ys, space_res, angle_res):
        """ScanMatcher::ComputePositionalCovariance."""
        cov = np.eye(3)
        if best < TOLERANCE:
            return np.diag([MAX_VARIANCE, MAX_VARIANCE, 4.0 * angle_res ** 2])
        dx, dy = mean[0] - center[0], mean[1] - center[1]
        norm = xx = xy = yy = 0.0
        for y in ys:
            gy = kernels.to_grid(center[1] + y, self.probs_offset[1], self.resolution)
            for x in xs:
                gx = kernels.to_grid(center[0] + x, self.probs_offset[0], self.resolution)
                response = self.probs[gy, gx]
                if response >= best - 0.1:
                    norm += response
                    xx += (x - dx) ** 2 * response
                    xy += (x - dx) * (y - dy) * response
                    yy += (y - dy) ** 2 * response
        if norm > TOLERANCE:
            floor_var = 0.1 * space_res ** 2
            multiplier = 1.0 / best
            cov[0, 0] = max(xx / norm, floor_var) * multiplier
            cov[0, 1] = cov[1, 0] = xy / norm * multiplier
            cov[1, 1] = max(yy / norm, floor_var) * multiplier
            cov[2, 2] = 4.0 * angle_res ** 2
        for i in (0, 1):
            if abs(cov[i, i]) < TOLERANCE:
                cov[i, i] = MAX_VARIANCE
        return cov

    def _angular_variance(self, mean, best, center, angles, offsets, angle_res) -> float:
        """ScanMatcher::ComputeAngularCovariance: the spread of the searched headings around
        the best heading (brought within π of the centre's, as NormalizeAngleDifference returns
        its minuend)."""
        best_angle = angle_near(mean[2], center[2])
        gx = kernels.to_grid(mean[0], self.offset[0], self.resolution)
        gy = kernels.to_grid(mean[1], self.offset[1], self.resolution)
        index = (gx + self.roi[0]) + (gy + self.roi[1]) * self.width_step
        norm = acc = 0.0
        for a, angle in enumerate(angles):
            response = kernels.response_at(self.grid, offsets, a, index)
            if response >= best - 0.1:
                norm += response
                acc += (angle - best_angle) ** 2 * response
        if norm > TOLERANCE:
            if acc < TOLERANCE:
                acc = angle_res ** 2
            return acc / norm
        return 1000.0 * angle_res ** 2
