"""Issue #4's map check on the shared real-robot logs, and what keeps aces below it.

For each log (default: intel, aces, csail, freiburg-101) prints:

- the reference trajectory's own consistency: point-to-point ICP between scan pairs ≥ 30 scans
  apart whose reference poses are within 1 m and 0.5 rad (the correction, m, median and 90th
  percentile), next to ICP between consecutive scans (the method's noise floor), the odometry's
  length against the reference's, and the agreement at 2 cells of the maps built from the first
  and the second half of the reference scans (counted where the other half has seen the area);
- with ``--seeds``: our GMapping run per seed (baseline parameters
  ../shared/baselines/gmapping_real_<log>.yaml, optionally overridden with ``--set k=v``): the
  error (m), the map check at 2 cells after the rigid trajectory fit
  (``runner.map_agreement_with_reference``), after a further rigid ICP of our map's occupied
  cells onto the reference's, and after a similarity (scale-free) trajectory fit.

Usage: bench/bench_gmapping_mapcheck.py [--logs aces ...] [--seeds 1 10] [--set srr=0.01 ...]
"""
from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from slam_predict.geometry import compose  # noqa: E402
from slam_predict.slam.compare import apply_transform, map_agreement, rigid_fit  # noqa: E402
from slam_predict.slam.gmapping.filter import centred_laser  # noqa: E402
from slam_predict.slam.gmapping.gridmap import MapBuilder  # noqa: E402
from slam_predict.slam.gmapping.params import load_params, with_ranges  # noqa: E402
from slam_predict.slam.runner import evaluate, read_input, run  # noqa: E402

SHARED = ROOT.parent / "shared"
TOL = 2.0  # cells


def scan_points(pose, ranges, angles, rmax=15.0):
    """Scan end points (M, 2) m in the world, beams 5 cm < r < ``rmax``."""
    ok = (ranges > 0.05) & (ranges < rmax)
    a = angles[ok] + pose[2]
    return np.c_[pose[0] + ranges[ok] * np.cos(a), pose[1] + ranges[ok] * np.sin(a)]


def icp(src, dst, iters=40, gate=0.5):
    """Point-to-point ICP of ``src`` onto ``dst`` → (translation (2,) m, rotation rad about the
    origin, share of matched points), or None when too few points match."""
    tree = cKDTree(dst)
    rot, trans, cur, matched = np.eye(2), np.zeros(2), src.copy(), 0.0
    for _ in range(iters):
        dist, k = tree.query(cur, distance_upper_bound=gate)
        ok = np.isfinite(dist)
        if ok.sum() < 30:
            return None
        p, q = cur[ok], dst[k[ok]]
        pc, qc = p.mean(0), q.mean(0)
        u, _, vt = np.linalg.svd((p - pc).T @ (q - qc))
        step = vt.T @ u.T
        if np.linalg.det(step) < 0:
            vt[1] *= -1
            step = vt.T @ u.T
        t = qc - step @ pc
        cur = cur @ step.T + t
        rot, trans, matched = step @ rot, step @ trans + t, ok.mean()
        if np.hypot(*t) < 1e-5:
            break
        gate = max(0.15, gate * 0.8)
    return trans, float(np.arctan2(rot[1, 0], rot[0, 0])), float(matched)


def pair_correction(poses, ranges, angles, i, j):
    """ICP correction (m) of scan j onto scan i, both placed with ``poses``; None if unmatched."""
    origin = poses[j, :2]
    res = icp(scan_points(poses[j], ranges[j], angles) - origin,
              scan_points(poses[i], ranges[i], angles) - origin)
    return None if res is None or res[2] < 0.6 else float(np.hypot(*res[0]))


def revisit_corrections(poses, ranges, angles, gap=30, dist=1.0, dth=0.5, max_pairs=400):
    """ICP corrections (m) of revisits: pairs ≥ ``gap`` scans apart within ``dist`` m and
    ``dth`` rad (at most ``max_pairs``, drawn with seed 0)."""
    pairs = []
    for i in range(len(poses)):
        j = np.arange(i + gap, len(poses))
        d = np.hypot(*(poses[j, :2] - poses[i, :2]).T)
        turn = np.abs(np.angle(np.exp(1j * (poses[j, 2] - poses[i, 2]))))
        pairs += [(i, int(k)) for k in j[(d < dist) & (turn < dth)]]
    if len(pairs) > max_pairs:
        keep = np.random.default_rng(0).choice(len(pairs), max_pairs, replace=False)
        pairs = [pairs[k] for k in keep]
    out = [pair_correction(poses, ranges, angles, i, j) for i, j in pairs]
    return np.array([c for c in out if c is not None])


def builder_for(data, params):
    laser_in_base, angles = centred_laser(data.laser)
    return MapBuilder(with_ranges(params, data.laser.range_max), angles), laser_in_base


def near_where_known(a, b, tol=TOL):
    """Share of a's occupied cells, among those b has seen, within ``tol`` cells of b's."""
    seen = a.copy()
    seen[b < 0] = -1
    return map_agreement(seen, b, tol)[0]


def reference_report(log, data, params):
    builder, laser_in_base = builder_for(data, params)
    angles = np.asarray(data.laser.angles)
    lasers = compose(data.reference, np.asarray(data.laser.pose_in_base))
    revisits = revisit_corrections(lasers, data.ranges, angles)
    floor = [pair_correction(lasers, data.ranges, angles, k, k + 1)
             for k in range(0, len(data) - 1, 3)]
    floor = np.array([c for c in floor if c is not None])
    ref = compose(data.reference, laser_in_base)
    half = len(data) // 2
    geometry = builder.geometry(ref, data.ranges)
    first = builder.render(geometry, ref[:half], data.ranges[:half]).data
    second = builder.render(geometry, ref[half:], data.ranges[half:]).data
    step_ref = np.linalg.norm(np.diff(data.reference[:, :2], axis=0), axis=1)
    step_odo = np.linalg.norm(np.diff(data.odometry[:, :2], axis=0), axis=1)
    print(f"{log} reference: revisit ICP {len(revisits)} pairs, correction median "
          f"{np.median(revisits):.3f} m, p90 {np.percentile(revisits, 90):.3f} m | consecutive "
          f"scans median {np.median(floor):.3f} m, p90 {np.percentile(floor, 90):.3f} m | "
          f"odometry/reference length {step_odo.sum() / step_ref.sum():.4f} | halves at 2 cells "
          f"{near_where_known(first, second):.3f} / {near_where_known(second, first):.3f}",
          flush=True)


def similarity_fitted(est, ref):
    """``est`` moved by the least-squares similarity (rotation, scale, translation) onto ``ref``
    (positions) → (poses (N, 3), scale)."""
    a, b = est[:, :2], ref[:, :2]
    ca, cb = a.mean(0), b.mean(0)
    h = (a - ca).T @ (b - cb)
    yaw = np.arctan2(h[0, 1] - h[1, 0], h[0, 0] + h[1, 1])
    rot = np.array([[np.cos(yaw), -np.sin(yaw)], [np.sin(yaw), np.cos(yaw)]])
    scale = float(np.sum((b - cb) * ((a - ca) @ rot.T)) / np.sum((a - ca) ** 2))
    out = est.copy()
    out[:, :2] = scale * (a - ca) @ rot.T + cb
    out[:, 2] = est[:, 2] + yaw
    return out, scale


def agreement(data, params, indices, poses):
    """(ours→ref, ref→ours) at 2 cells for map-frame robot ``poses`` already in the reference
    frame, and our grid and the reference grid (as runner.map_agreement_with_reference)."""
    builder, laser_in_base = builder_for(data, params)
    ours = compose(poses, laser_in_base)
    ref = compose(data.reference[indices], laser_in_base)
    readings = data.ranges[indices]
    geometry = builder.geometry(ref, readings, start=builder.geometry(ours, readings))
    a, b = builder.render(geometry, ours, readings), builder.render(geometry, ref, readings)
    return map_agreement(a.data, b.data, TOL), a, b


def occupied_points(grid):
    rows, cols = np.nonzero(grid.data >= 100)
    return np.c_[grid.origin[0] + cols * grid.resolution, grid.origin[1] + rows * grid.resolution]


def map_icp_transform(ours_grid, ref_grid):
    """Rigid transform (x, y, yaw) moving our map's occupied cells onto the reference's."""
    p, q = occupied_points(ours_grid), occupied_points(ref_grid)
    centre = p.mean(0)
    t, yaw, _ = icp(p - centre, q - centre, iters=60, gate=1.0)
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([t[0] + centre[0] - (c * centre[0] - s * centre[1]),
                     t[1] + centre[1] - (s * centre[0] + c * centre[1]), yaw])


def run_report(log, data, params, seed):
    result = run(data, "gmapping", params, seed)
    idx, ref = result.indices, data.reference[result.indices]
    error = evaluate(result)["slam"]["trans_mean_m"]
    fitted = apply_transform(rigid_fit(result.poses, ref), result.poses)
    (a, b), ours_grid, ref_grid = agreement(data, params, idx, fitted)
    move = map_icp_transform(ours_grid, ref_grid)
    (a2, b2), _, _ = agreement(data, params, idx, apply_transform(move, fitted))
    similar, scale = similarity_fitted(result.poses, ref)
    (a3, b3), _, _ = agreement(data, params, idx, similar)
    print(f"{log} seed {seed}: error {error:.3f} m | 2 cells: rigid fit {a:.3f} / {b:.3f} | "
          f"+ map ICP ({np.hypot(*move[:2]):.3f} m, {np.degrees(move[2]):.2f} deg) {a2:.3f} / "
          f"{b2:.3f} | similarity fit (scale {scale:.4f}) {a3:.3f} / {b3:.3f}", flush=True)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--logs", nargs="+", default=["intel", "aces", "csail", "freiburg-101"])
    parser.add_argument("--seeds", nargs="*", type=int, default=[])
    parser.add_argument("--set", nargs="*", default=[], metavar="KEY=VALUE",
                        help="GMapping parameter overrides, e.g. srr=0.01 particles=40")
    parser.add_argument("--no-reference", action="store_true", help="skip the reference checks")
    args = parser.parse_args()
    overrides = {k: (int(v) if v.lstrip("-").isdigit() else float(v))
                 for k, v in (item.split("=", 1) for item in args.set)}
    for log in args.logs:
        data = read_input(SHARED / "data" / "slam_inputs" / f"{log}.log.gz")
        params = load_params(SHARED / "baselines" / f"gmapping_real_{log}.yaml")
        params = dataclasses.replace(params, **overrides)
        if not args.no_reference:
            reference_report(log, data, params)
        for seed in args.seeds:
            run_report(log, data, params, seed)
    return 0


if __name__ == "__main__":
    sys.exit(main())
