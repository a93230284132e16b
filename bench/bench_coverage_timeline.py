#!/usr/bin/env python3
"""When a collected run reached full coverage, and how far it drove after that.

For each run folder (``WORLD/run_NNN/`` as collected: run.json, ``snapshots/``, slam_scans.tum,
ground_truth.tum; the committed run.json alone is not enough):

- the share of the reachable floor the laser had swept, every ``--step`` s, from the robot's true
  poses at the scans the SLAM back-end processed (``explore.seen``: the exploration, without
  the SLAM map's error), and when (s, path driven by then) it first reached ``--full`` and
  all it would reach (its final share − 0.005);
- at the end: the path, the episode's coverage (known cells of the final SLAM map laid on the
  plan from the start pose, ``explore.coverage``) and the swept share;
- the path driven after the laser had swept all it would (the tail the stop rule adds while
  GMapping's map keeps changing, docs/notes/exploration.md), and the snapshots' MSE.

With ``--thesis``, each building's seed-study path (``totalLen``) beside it; ``--json`` also
writes every snapshot's map coverage, swept share and path.

    python bench/bench_coverage_timeline.py data/campaigns/fidelity_seed_study_3 \\
        [--worlds Neulengbach1_updated NLB] [--thesis ../shared/data/thesis/stats_realistic.csv]

Run it from the folder the campaign was collected in (run.json's ``world_file`` is relative
to it).
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from types import SimpleNamespace

import cv2
import numpy as np

from slam_predict.formats.mapserver import FREE, OCCUPIED
from slam_predict.formats.tum import read_tum

CANVAS_ORIGIN = (-100.0, -100.0)   # m: slam_gmapping's xmin/ymin, the snapshots' lower-left
RESOLUTION = 0.05                  # m: GMapping's delta (the snapshot's cell)


def snapshot_grid(path: Path):
    """A snapshot PNG as a grid (data: −1 unknown, 0 free, 100 occupied; row 0 = bottom)."""
    image = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE)
    data = np.full(image.shape, -1, np.int8)
    data[image == FREE] = 0
    data[image == OCCUPIED] = 100
    return SimpleNamespace(data=data[::-1], origin=CANVAS_ORIGIN, resolution=RESOLUTION)


def path_by_time(ground_truth: Path) -> tuple[np.ndarray, np.ndarray]:
    """Times (s) and cumulative path (m) of a ground-truth TUM file."""
    times, poses = read_tum(ground_truth)
    steps = np.hypot(*np.diff(poses[:, :2], axis=0).T)
    return times, np.concatenate([[0.0], np.cumsum(steps)])


def laser_of(record: dict):
    """The run's laser (run.json ``sensor``) as a :class:`slam_predict.sensor.LaserConfig`."""
    from slam_predict.sensor import LaserConfig

    fields = ("fov", "samples", "range_min", "range_max", "pose")
    return LaserConfig(**{k: record["sensor"]["laser"][k] for k in fields})


def swept_curve(run: Path, record: dict, world, settings, reach: np.ndarray,
                step_s: float) -> tuple[np.ndarray, np.ndarray]:
    """Times (every ``step_s`` s to the run's end) and the share of the reachable floor the
    laser had swept by then (``explore.seen``), from the scans the SLAM back-end processed,
    with the laser of run.json's ``sensor``."""
    from slam_predict.explore.seen import poses_at, seen_mask, seen_share, usable_range

    scan_times, _ = read_tum(run / "slam_scans.tum")
    truth_times, truth = read_tum(run / "ground_truth.tum")
    poses = poses_at(scan_times, truth_times, truth)
    laser = laser_of(record)
    angles, reach_m = laser.angles(), usable_range(settings.slam.params, laser.range_max)
    times = np.arange(step_s, record["sim_duration_s"] + step_s / 2, step_s)
    seen = np.zeros(world.occupied.shape, bool)
    shares, start = [], 0
    for t in times:
        stop = int(np.searchsorted(scan_times, t + 1e-9, side="right"))
        seen |= seen_mask(world, poses[start:stop], laser.pose, angles, reach_m)
        shares.append(seen_share(reach, seen))
        start = stop
    return times, np.array(shares)


def load_run(run: Path):
    """(run.json, World, settings, reachable floor) of a run folder."""
    from slam_predict.collect.settings import load_settings
    from slam_predict.explore.coverage import reachable_free
    from slam_predict.nav.costmap import inscribed_radius
    from slam_predict.world.load import load_plan

    record = json.loads((run / "run.json").read_text())
    world = load_plan(Path(record["world_file"]))
    settings = load_settings(record["settings_file"])
    reach = reachable_free(world, inscribed_radius(settings.nav.global_costmap))
    return record, world, settings, reach


def timeline(run: Path, full: float, step_s: float) -> dict:
    """The run's snapshots (map coverage, swept share, path) and when it had swept ``full``
    of the floor and all it would sweep (within 0.005 of its final share)."""
    from slam_predict.explore.coverage import coverage

    record, world, settings, reach = load_run(run)
    times, path = path_by_time(run / "ground_truth.tum")
    curve_t, swept = swept_curve(run, record, world, settings, reach, step_s)
    snaps = []
    for k, snap in enumerate(record["snapshots"], start=1):
        grid = snapshot_grid(run / "snapshots" / f"snapshot_{k:02d}.png")
        snaps.append({"t": snap["t"], "mse": snap["mse"],
                      "path_m": float(np.interp(snap["t"], times, path)),
                      "coverage": coverage(world, grid, reach, world.start_pose),
                      "swept": float(np.interp(snap["t"], curve_t, swept))})

    def reached(share: float) -> dict | None:
        hit = np.flatnonzero(swept >= share)
        if not hit.size:
            return None
        t = float(curve_t[hit[0]])
        return {"t": t, "path_m": float(np.interp(t, times, path))}

    return {"world": record["world"], "run": run.name, "snapshots": snaps,
            "end_t": record["sim_duration_s"], "end_path_m": record["distance_m"],
            "end_coverage": record["coverage"], "end_swept": float(swept[-1]),
            "swept_full": reached(full), "swept_all": reached(float(swept[-1]) - 0.005)}


def floor_picture(run: Path) -> np.ndarray:
    """RGB image of the plan (row 0 = top): walls black, the reachable floor green where the
    laser swept it and the final SLAM map (map.pgm, laid from the start pose) knows it, orange
    where it was swept but the map, drifted, has it unknown, red where the laser never swept
    it; the true path in blue."""
    from slam_predict.geometry import compose, inverse

    record, world, settings, reach = load_run(run)
    seen = _swept_mask(run, record, world, settings)
    grid = snapshot_grid(run / "map.pgm")
    rows, cols = np.nonzero(reach)
    centres = world.cell_to_world(np.stack([rows, cols], axis=1))
    in_map = compose(inverse(world.start_pose),
                     np.column_stack([centres, np.zeros(len(rows))]))[:, :2]
    gx = np.floor((in_map[:, 0] - grid.origin[0]) / grid.resolution).astype(int)
    gy = np.floor((in_map[:, 1] - grid.origin[1]) / grid.resolution).astype(int)
    known = grid.data[gy, gx] != -1
    image = np.full(world.occupied.shape + (3,), 255, np.uint8)
    image[world.occupied] = 0
    colours = np.where(known[:, None], (150, 210, 150), (255, 160, 0))
    colours[~seen[rows, cols]] = (230, 0, 0)
    image[rows, cols] = colours
    _, truth = read_tum(run / "ground_truth.tum")
    cells = np.array([world.world_to_cell(p[:2]) for p in truth[::5]])
    inside = ((cells >= 0) & (cells < world.occupied.shape)).all(axis=1)
    image[cells[inside, 0], cells[inside, 1]] = (40, 80, 230)
    return image


def _swept_mask(run: Path, record: dict, world, settings) -> np.ndarray:
    """The whole run's laser-swept floor (bool mask over the plan)."""
    from slam_predict.explore.seen import poses_at, seen_mask, usable_range

    scan_times, _ = read_tum(run / "slam_scans.tum")
    truth_times, truth = read_tum(run / "ground_truth.tum")
    laser = laser_of(record)
    return seen_mask(world, poses_at(scan_times, truth_times, truth), laser.pose,
                     laser.angles(), usable_range(settings.slam.params, laser.range_max))


def thesis_paths(csv_path: Path | None) -> dict[str, float]:
    """Building → the seed study's mean path (m)."""
    if csv_path is None:
        return {}
    from slam_predict.collect.fidelity import read_thesis_table

    return {name: row["path_length_mean"] for name, row in read_thesis_table(csv_path).items()}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("campaign", type=Path)
    parser.add_argument("--worlds", nargs="+", help="only these buildings")
    parser.add_argument("--full", type=float, default=0.95, help="full coverage (share)")
    parser.add_argument("--step", type=float, default=30.0, help="s between swept shares")
    parser.add_argument("--thesis", type=Path, help="the seed study's stats table")
    parser.add_argument("--json", type=Path, help="also write every snapshot's figures here")
    args = parser.parse_args(argv)
    theirs = thesis_paths(args.thesis)
    runs = sorted(p.parent for p in args.campaign.glob("*/run_*/run.json")
                  if (p.parent / "snapshots").is_dir()
                  and (args.worlds is None or p.parent.parent.name in args.worlds))
    rows = [timeline(run, args.full, args.step) for run in runs]
    print(f"| building | run | seed study's path m | swept {args.full:g}: s, path m | swept all "
          "(final − 0.005): s, path m | end: s, path m | map coverage / swept at the end "
          "| path after sweeping all, m | snapshots' MSE |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        theirs_m = theirs.get(r["world"])
        cells = [f"{e['t']:.0f}, {e['path_m']:.0f}" if e else "never"
                 for e in (r["swept_full"], r["swept_all"])]
        mses = ", ".join("–" if s["mse"] is None else f"{s['mse']:.1f}" for s in r["snapshots"])
        print(f"| {r['world']} | {r['run']} | {'' if theirs_m is None else f'{theirs_m:.0f}'} "
              f"| {cells[0]} | {cells[1]} | {r['end_t']:.0f}, {r['end_path_m']:.0f} "
              f"| {r['end_coverage']:.3f} / {r['end_swept']:.3f} "
              f"| {r['end_path_m'] - r['swept_all']['path_m']:.0f} | {mses} |")
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
