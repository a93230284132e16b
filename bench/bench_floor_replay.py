"""Where our SLAM error floor comes from (issue #16): offline replays of collected runs with the
odometry, the filter or the map resolution changed, the scans and the path kept.

A collected run with ``sensor_logs`` (its sensors.bag, or sensors.log.gz) is replayed through our
GMapping exactly as the closed loop ran it (same parameters and generator: the ``recorded``
row reproduces the run's ``slam_scans.tum``), then with variants:

- ``--odometry truth``: the odometry replaced by the ground truth (a perfect odometer); with
  ``--scale S`` the ground truth's translations scaled by S (a pure scale error, no heading
  error);
- ``--override KEY=VALUE`` (repeatable): GMapping parameters over the run's (e.g. particles=1,
  srr=0, delta=0.025, range_sensor_angles=false);
- ``--turn-frame RAD`` / ``--shift-frame M``: the odometry (and ground truth) expressed in a frame
  turned about / shifted from the original, which lays GMapping's grid differently over the
  walls (the scans are unchanged).

Each row: relation errors (random forward pairs over the processed scans, mean, not squared:
the seed study's data release) of the SLAM poses and of the odometry handed to it, against the
ground truth, on the scans up to ``--max-time`` s (the exploration; the end of a run is the robot
standing still); and the SLAM trajectory's shape against the ground truth: its length ratio
(summed relation lengths, SLAM ÷ true: below 1 the trajectory is shrunk), the rotation of its
positions (rad, least squares) and what is left after that rigid fit (rms, m).

Usage: bench/bench_floor_replay.py RUN_DIR [RUN_DIR ...] [--odometry recorded truth]
       [--scale S] [--override KEY=VALUE ...] [--max-time S] [--pairs N]
"""
from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from slam_predict.geometry import compose, inverse  # noqa: E402
from slam_predict.metric.relations import random_forward_pairs, relation_errors  # noqa: E402
from slam_predict.slam.runner import read_input, recorded_run, run  # noqa: E402


def scaled_truth(reference: np.ndarray, scale: float) -> np.ndarray:
    """An odometer that follows ``reference`` (N, 3) exactly in heading and measures each step's
    translation (in the robot frame) ``scale`` times too long, integrated from the first pose."""
    if scale == 1.0:
        return np.array(reference, dtype=float)   # exactly the ground truth, no rounding
    odometry = np.empty_like(reference)
    odometry[0] = reference[0]
    for k in range(1, len(reference)):
        step = compose(inverse(reference[k - 1]), reference[k])
        step[:2] *= scale
        odometry[k] = compose(odometry[k - 1], step)
        odometry[k, 2] = reference[k, 2]
    return odometry


def in_turned_frame(poses: np.ndarray, angle: float, shift: float) -> np.ndarray:
    """``poses`` (N, 3) in a frame turned by ``angle`` rad about the origin, then shifted by
    ``shift`` m along both axes: the same motion, another map frame."""
    c, s = np.cos(angle), np.sin(angle)
    out = np.array(poses, dtype=float)
    out[:, 0] = c * poses[:, 0] - s * poses[:, 1] + shift
    out[:, 1] = s * poses[:, 0] + c * poses[:, 1] + shift
    out[:, 2] = poses[:, 2] + angle
    return out


def summed_lengths(xy: np.ndarray, pairs: np.ndarray) -> float:
    """Sum of the straight-line distances (m) between the positions ``xy`` (N, 2) of each pair."""
    return float(np.linalg.norm(xy[pairs[:, 1]] - xy[pairs[:, 0]], axis=1).sum())


def trajectory_shape(estimate: np.ndarray, reference: np.ndarray, pairs: np.ndarray
                     ) -> tuple[float, float, float]:
    """(length ratio, rotation rad, residual rms m) of ``estimate`` against ``reference`` (N, 3):
    summed relation lengths over ``pairs`` (SLAM ÷ true); the least-squares rotation taking the
    centred reference positions onto the centred estimate; the rms of what a rigid fit leaves."""
    est, ref = estimate[:, :2], reference[:, :2]
    ratio = float(summed_lengths(est, pairs) / summed_lengths(ref, pairs))
    est_c, ref_c = est - est.mean(axis=0), ref - ref.mean(axis=0)
    cross = np.sum(ref_c[:, 0] * est_c[:, 1] - ref_c[:, 1] * est_c[:, 0])
    dot = np.sum(ref_c * est_c)
    angle = float(np.arctan2(cross, dot))
    c, s = np.cos(angle), np.sin(angle)
    fitted = np.column_stack([c * ref_c[:, 0] - s * ref_c[:, 1], s * ref_c[:, 0] + c * ref_c[:, 1]])
    residual = float(np.sqrt(np.mean(np.sum((est_c - fitted) ** 2, axis=1))))
    return ratio, angle, residual


def parse_overrides(items: list[str]) -> dict:
    """KEY=VALUE strings → typed values (bool, int, float or text)."""
    out = {}
    for item in items:
        key, _, text = item.partition("=")
        lowered = text.strip().lower()
        if lowered in ("true", "false"):
            out[key] = lowered == "true"
            continue
        try:
            out[key] = int(text)
        except ValueError:
            try:
                out[key] = float(text)
            except ValueError:
                out[key] = text
    return out


def relation_figures(estimate: np.ndarray, reference: np.ndarray, pairs: int,
                     seed: int = 1) -> tuple[float, float]:
    """(ε_t m, ε_r rad): mean relation errors of ``estimate`` against ``reference``."""
    chosen = random_forward_pairs(len(reference), pairs, np.random.default_rng(seed))
    errors = relation_errors(estimate, reference, chosen)
    return float(errors.trans.mean()), float(errors.rot.mean())


def replay(run_dir: Path, odometry: str, scale: float, overrides: dict, max_time: float,
           pairs: int, turn: float = 0.0, shift: float = 0.0) -> dict:
    """One replay of a collected run; its figures."""
    source = run_dir / "sensors.bag"
    if not source.exists():
        source = run_dir / "sensors.log.gz"
    recorded = recorded_run(source)
    if recorded is None:
        raise SystemExit(f"{run_dir}: no run.json with sensor_logs beside {source.name}")
    data = read_input(source)
    keep = np.flatnonzero(data.times <= max_time)
    data = data.take(keep)
    if odometry == "truth":
        data = dataclasses.replace(data, odometry=scaled_truth(data.reference, scale))
    if turn or shift:
        data = dataclasses.replace(data, odometry=in_turned_frame(data.odometry, turn, shift),
                                   reference=in_turned_frame(data.reference, turn, shift))
    params = dataclasses.replace(recorded.params, **overrides) if overrides else recorded.params
    result = run(data, recorded.slam_type, params, recorded.seed, rng=recorded.rng())
    slam_t, slam_r = relation_figures(result.poses, result.reference, pairs)
    odom_t, odom_r = relation_figures(result.odometry, result.reference, pairs)
    chosen = random_forward_pairs(len(result.reference), pairs, np.random.default_rng(1))
    return {"scans": int(result.stats["scans_processed"]), "slam": (slam_t, slam_r),
            "odometry": (odom_t, odom_r),
            "shape": trajectory_shape(result.poses, result.reference, chosen)}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("runs", type=Path, nargs="+")
    parser.add_argument("--odometry", nargs="+", default=["recorded", "truth"],
                        choices=["recorded", "truth"])
    parser.add_argument("--scale", type=float, default=1.0)
    parser.add_argument("--override", action="append", default=[], metavar="KEY=VALUE")
    parser.add_argument("--max-time", type=float, default=float("inf"))
    parser.add_argument("--pairs", type=int, default=20000)
    parser.add_argument("--turn-frame", type=float, default=0.0, metavar="RAD")
    parser.add_argument("--shift-frame", type=float, default=0.0, metavar="M")
    args = parser.parse_args(argv)
    overrides = parse_overrides(args.override)
    label = ", ".join(f"{k}={v}" for k, v in overrides.items()) or "as recorded"
    frame = f"; frame turned {args.turn_frame:g} rad, shifted {args.shift_frame:g} m" \
        if args.turn_frame or args.shift_frame else ""
    print(f"GMapping: {label}; scans up to {args.max_time:g} s{frame}")
    print("| run | odometry | scans | ε_t SLAM (m) | ε_r SLAM (rad) | ε_t odometry (m) | "
          "ε_r odometry (rad) | length ratio | rotation (rad) | residual (m) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for run_dir in args.runs:
        for odometry in args.odometry:
            name = odometry if odometry == "recorded" or args.scale == 1.0 \
                else f"truth ×{args.scale:g}"
            f = replay(run_dir, odometry, args.scale, overrides, args.max_time, args.pairs,
                       args.turn_frame, args.shift_frame)
            ratio, angle, residual = f["shape"]
            print(f"| {run_dir.parent.name}/{run_dir.name} | {name} | {f['scans']} | "
                  f"{f['slam'][0]:.4f} | {f['slam'][1]:.5f} | {f['odometry'][0]:.4f} | "
                  f"{f['odometry'][1]:.5f} | {ratio:.4f} | {angle:+.5f} | {residual:.4f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
