"""Karto's MapperGraph: the edges a new scan gets (previous scan, running scans, near chains),
loop closure against chains of old scans, and the pose correction after each closure."""
from __future__ import annotations

import math
from collections import deque

import numpy as np

from slam_predict.slam.karto.scan import ORIGIN, TOLERANCE, LocalizedScan, transform_pose
from slam_predict.slam.karto.solver import PoseGraphSolver, karto_inverse


def rotated_covariance(covariance, heading: float) -> np.ndarray:
    """LinkInfo: the covariance turned into the frame of the source pose (heading rad)."""
    c, s = math.cos(-heading), math.sin(-heading)
    rotation = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    return rotation @ np.asarray(covariance) @ rotation.T


def weighted_mean(means, covariances) -> np.ndarray:
    """Mapper::ComputeWeightedMean: information-weighted poses, the heading the circular mean
    (Karto's Matrix3 products and sums, term by term in its order)."""
    inverses = [karto_inverse(c) for c in covariances]
    total_information = np.zeros((3, 3))
    for inverse in inverses:
        total_information = total_information + inverse
    scale = karto_inverse(total_information)
    total = [0.0, 0.0, 0.0]
    theta_x = theta_y = 0.0
    for mean, inverse in zip(means, inverses, strict=True):
        theta_x += math.cos(mean[2])
        theta_y += math.sin(mean[2])
        weight = matrix_product(scale, inverse)
        for row in range(3):
            total[row] += (weight[row][0] * mean[0] + weight[row][1] * mean[1]
                           + weight[row][2] * mean[2])
    count = len(means)
    return np.array([total[0], total[1], math.atan2(theta_y / count, theta_x / count)])


def matrix_product(a, b) -> list:
    """Karto's Matrix3 product, each entry summed left to right."""
    a, b = np.asarray(a).tolist(), np.asarray(b).tolist()
    return [[a[r][0] * b[0][c] + a[r][1] * b[1][c] + a[r][2] * b[2][c] for c in range(3)]
            for r in range(3)]


class MapperGraph:
    """Vertices are the Mapper's scans (by unique id); edges kept per vertex in insertion order."""

    def __init__(self, mapper):
        self.mapper = mapper
        self.p = mapper.p
        self.adjacent: list[list[int]] = []
        self.edge_set: set[tuple[int, int]] = set()
        self.solver = PoseGraphSolver()
        self.loop_closures: list[tuple[int, int]] = []
        self.loop_matcher = None

    def reference(self, scan: LocalizedScan) -> np.ndarray:
        """GetReferencePose: the barycenter of the points or the sensor position."""
        return scan.barycenter if self.p.use_scan_barycenter else scan.sensor_pose[:2]

    def add(self, scan: LocalizedScan, covariance) -> None:
        """AddVertex then AddEdges (Karto's order)."""
        self.adjacent.append([])
        self.solver.add_node(scan.corrected_pose)
        scans = self.mapper.scans
        if scan.unique_id == 0:
            return
        self.link(scans[scan.unique_id - 1], scan, scan.sensor_pose, covariance)
        means, covariances = [scan.sensor_pose], [covariance]
        self.link_chain(self.mapper.running, scan, scan.sensor_pose, covariance)
        self.link_near_chains(scan, means, covariances)
        scan.set_sensor_pose(weighted_mean(means, covariances))

    def link(self, source: LocalizedScan, target: LocalizedScan, mean, covariance) -> bool:
        """LinkScans: a new edge source → target carrying the robot pose of ``mean`` (a sensor
        pose) in the frame of source's corrected pose."""
        key = (source.unique_id, target.unique_id)
        if key in self.edge_set:
            return False
        self.edge_set.add(key)
        self.adjacent[source.unique_id].append(target.unique_id)
        self.adjacent[target.unique_id].append(source.unique_id)
        origin = source.corrected_pose
        self.solver.add_constraint(source.unique_id, target.unique_id,
                                   transform_pose(origin, ORIGIN, target.corrected_at(mean)),
                                   rotated_covariance(covariance, origin[2]))
        return True

    def link_chain(self, chain, scan, mean, covariance) -> int:
        """LinkChainToScan: link the chain scan nearest to the scan (if within
        link_scan_maximum_distance); its unique id, or −1."""
        here = self.reference(scan)
        closest, best = None, math.inf
        for candidate in chain:
            d = float(np.sum((self.reference(candidate) - here) ** 2))
            if d < best:
                closest, best = candidate, d
        if closest is None or best >= self.p.link_scan_maximum_distance ** 2 + TOLERANCE:
            return -1
        return closest.unique_id if self.link(closest, scan, mean, covariance) else -1

    def near_linked(self, scan, distance: float) -> list[LocalizedScan]:
        """FindNearLinkedScans: breadth-first over edges while the reference points stay
        within ``distance`` m of the scan's."""
        scans = self.mapper.scans
        centre = self.reference(scan)
        limit = distance ** 2 - TOLERANCE
        seen, queue, found = {scan.unique_id}, deque([scan.unique_id]), []
        while queue:
            vertex = queue.popleft()
            if float(np.sum((self.reference(scans[vertex]) - centre) ** 2)) > limit:
                continue
            found.append(scans[vertex])
            for other in self.adjacent[vertex]:
                if other not in seen:
                    seen.add(other)
                    queue.append(other)
        return found

    def near_chains(self, scan) -> list[list[LocalizedScan]]:
        """FindNearChains: runs of consecutive scans around each near linked scan (distances
        between reference points, as Karto's GetReferencePose)."""
        scans = self.mapper.scans
        position = self.reference(scan)
        limit = self.p.link_scan_maximum_distance ** 2 + TOLERANCE
        processed: set[int] = set()
        chains = []
        for near in self.near_linked(scan, self.p.link_scan_maximum_distance):
            if near is scan or near.unique_id in processed:
                continue
            processed.add(near.unique_id)
            valid, before, after = True, [], []
            for step, out in ((-1, before), (1, after)):
                k = near.unique_id + step
                while 0 <= k < len(scans):
                    candidate = scans[k]
                    if candidate is scan:
                        valid = False
                    if float(np.sum((self.reference(candidate) - position) ** 2)) >= limit:
                        break
                    out.append(candidate)
                    processed.add(candidate.unique_id)
                    k += step
            if valid:
                chains.append(before[::-1] + [near] + after)
        return chains

    def link_near_chains(self, scan, means, covariances) -> None:
        """LinkNearChains: match against each long-enough near chain (no penalty)."""
        for chain in self.near_chains(scan):
            if len(chain) < self.p.loop_match_minimum_chain_size:
                continue
            response, mean, cov = self.mapper.matcher.match(scan, chain, penalize=False)
            if response > self.p.link_match_minimum_response_fine - TOLERANCE:
                means.append(mean)
                covariances.append(cov)
                self.link_chain(chain, scan, mean, cov)

    def possible_loop_closure(self, scan, start: int):
        """FindPossibleLoopClosure from scan number ``start``: (chain, next start)."""
        scans = self.mapper.scans
        here = self.reference(scan)
        linked = {s.unique_id for s in self.near_linked(scan, self.p.loop_search_maximum_distance)}
        limit = self.p.loop_search_maximum_distance ** 2 + TOLERANCE
        chain: list[LocalizedScan] = []
        while start < len(scans):
            candidate = scans[start]
            start += 1
            if float(np.sum((self.reference(candidate) - here) ** 2)) < limit:
                if candidate.unique_id in linked:
                    chain = []
                else:
                    chain.append(candidate)
            elif len(chain) >= self.p.loop_match_minimum_chain_size:
                return chain, start
            else:
                chain = []
        return chain, start

    def try_close_loop(self, scan) -> bool:
        """TryCloseLoop: coarse match on the loop grid, fine match of a copy at the coarse
        pose, link and optimise when both pass."""
        closed = False
        chain, start = self.possible_loop_closure(scan, 0)
        while chain:
            response, best, cov = self.mapper.loop_matcher().match(scan, chain, penalize=False,
                                                                   refine=False)
            limit = self.p.loop_match_maximum_variance_coarse ** 2   # squared by its setter
            if (response > self.p.loop_match_minimum_response_coarse and cov[0, 0] < limit
                    and cov[1, 1] < limit):
                probe = LocalizedScan(scan.laser, scan.input_index, scan.time,
                                      scan.odometric_pose, scan.ranges,
                                      corrected_pose=scan.corrected_pose.copy())
                probe.set_sensor_pose(best)
                fine, best, cov = self.mapper.matcher.match(probe, chain, penalize=False)
                if fine >= self.p.loop_match_minimum_response_fine:
                    scan.set_sensor_pose(best)
                    linked = self.link_chain(chain, scan, best, cov)
                    self.loop_closures.append((scan.input_index, chain_index(chain, linked)))
                    self.correct_poses()
                    closed = True
            chain, start = self.possible_loop_closure(scan, start)
        return closed

    def correct_poses(self) -> None:
        """CorrectPoses: optimise, then every scan takes its node's pose (none moves when the
        solver has no usable solution)."""
        poses = self.solver.solve()
        if poses is None:
            return
        for scan, pose in zip(self.mapper.scans, poses, strict=True):
            scan.set_corrected_pose(pose)


def chain_index(chain, unique_id: int) -> int:
    """The input index of the chain scan with ``unique_id`` (−1 when none was linked)."""
    return next((s.input_index for s in chain if s.unique_id == unique_id), -1)
