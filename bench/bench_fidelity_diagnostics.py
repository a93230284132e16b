"""Where our errors part from the seed study's (issue #16): heading error vs distance and rotation.

For each building of a campaign folder (written by ``slam-predict collect`` with its trajectory
files kept, i.e. not a fresh clone: only run.json is committed), over the runs found:

- ``dbar``: mean ground-truth distance (m) between the two poses of a random forward relation;
- ``k_ours`` = ε_t / (dbar · ε_r) of our runs and ``k_theirs`` the same with the seed study's
  ε_t, ε_r (``transError.mean.mean``, ``rotError.mean.mean``) and our dbar. k ≈ 1 on both sides
  means ε_t is mostly the heading error ε_r acting over the pair distance, so a gap in ε_t comes
  from a gap in ε_r;
- ``D_ours`` / ``D_theirs`` = ε_r² / total rotation (rad²/rad): how fast the relation heading
  error grows with the rotation driven. A heading error that random-walks with rotation keeps
  D constant across buildings;
- ε_r of our relations binned by the rotation driven between their two poses (rad): a random
  walk keeps growing across bins, a bounded error levels off.

Relations: ``--pairs`` random forward pairs over the run's ground-truth poses after the thesis'
pause removal, seeded (``--seed``); mean (not squared) errors, as the seed study's data release.

Usage: bench/bench_fidelity_diagnostics.py CAMPAIGN_DIR [--thesis CSV] [--pairs N] [--seed N]
"""
from __future__ import annotations

import argparse
import csv
import os
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from slam_predict.formats.tum import read_tum  # noqa: E402
from slam_predict.geometry import wrap_angle  # noqa: E402
from slam_predict.metric.evaluate import StampedPoses, aligned  # noqa: E402
from slam_predict.metric.relations import random_forward_pairs, relation_errors  # noqa: E402

SHARED_DATA = Path(os.environ.get("SLAM_PREDICT_SHARED", ROOT.parent / "shared")) / "data"
ROTATION_BINS = (0.0, 1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 1000.0, 3000.0)  # rad


def run_relations(run_dir: Path, n_pairs: int, rng: np.random.Generator):
    """(trans errors m, rot errors rad, pair distances m, pair rotations rad, total rotation rad)
    of one run's random relations (SLAM vs ground truth)."""
    # the metric's own pairing: pause removal on the ground truth, association by timestamp
    _, slam, gt = aligned(StampedPoses(*read_tum(run_dir / "slam.tum")),
                          StampedPoses(*read_tum(run_dir / "ground_truth.tum")))
    pairs = random_forward_pairs(len(gt), n_pairs, rng)
    errors = relation_errors(slam, gt, pairs)
    distance = np.hypot(*(gt[pairs[:, 1], :2] - gt[pairs[:, 0], :2]).T)
    turned = np.concatenate([[0.0], np.cumsum(np.abs(wrap_angle(np.diff(gt[:, 2]))))])
    rotation = turned[pairs[:, 1]] - turned[pairs[:, 0]]
    return errors.trans, errors.rot, distance, rotation, float(turned[-1])


def building_figures(runs: list[Path], n_pairs: int, seed: int) -> dict:
    """Pooled relations of a building's runs → dbar, ε_t, ε_r, mean total rotation, the
    ε_r profile over ROTATION_BINS."""
    rng = np.random.default_rng(seed)
    parts = [run_relations(run, n_pairs, rng) for run in runs]
    trans, rot, dist, turned = (np.concatenate([p[i] for p in parts]) for i in range(4))
    profile = []
    for low, high in zip(ROTATION_BINS[:-1], ROTATION_BINS[1:], strict=True):
        inside = (turned >= low) & (turned < high)
        if inside.sum() >= 50:
            profile.append(f"[{low:g},{high:g}) {rot[inside].mean():.4f}")
    return {"dbar": dist.mean(), "et": trans.mean(), "er": rot.mean(),
            "R": float(np.mean([p[4] for p in parts])), "profile": " ".join(profile)}


def read_thesis(path: Path) -> dict[str, dict[str, float]]:
    """The seed study's ε_t (m), ε_r (rad) and total rotation (rad) by building name."""
    with open(path, newline="", encoding="utf-8") as handle:
        rows = list(csv.DictReader(handle, skipinitialspace=True))
    return {r["dataset"].strip(): {"trans": float(r["transError.mean.mean"]),
                                   "rot": float(r["rotError.mean.mean"]),
                                   "rotation": float(r["totalRot"])} for r in rows}


def thesis_row(thesis: dict, world: str) -> dict | None:
    """The seed study's row of ``world`` (names with or without the ``_updated`` suffix)."""
    return thesis.get(world) or thesis.get(world.removesuffix("_updated"))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("campaign", type=Path)
    parser.add_argument("--thesis", type=Path, default=SHARED_DATA / "thesis" /
                        "stats_realistic.csv")
    parser.add_argument("--pairs", type=int, default=20000, help="relations per run")
    parser.add_argument("--seed", type=int, default=3)
    args = parser.parse_args(argv)
    thesis = read_thesis(args.thesis)
    print("| building | runs | dbar m | ε_t ours / theirs m | ε_r ours / theirs rad | k ours | "
          "k theirs | D ours | D theirs | ours: ε_r by rotation between the poses (rad) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for building in sorted(p for p in args.campaign.iterdir() if p.is_dir()):
        runs = sorted(r for r in building.glob("run_*") if (r / "slam.tum").is_file())
        theirs = thesis_row(thesis, building.name)
        if not runs or theirs is None:
            continue
        f = building_figures(runs, args.pairs, args.seed)
        k_ours = f["et"] / (f["dbar"] * f["er"])
        k_theirs = theirs["trans"] / (f["dbar"] * theirs["rot"])
        print(f"| {building.name} | {len(runs)} | {f['dbar']:.1f} | {f['et']:.3f} / "
              f"{theirs['trans']:.3f} | {f['er']:.4f} / {theirs['rot']:.4f} | {k_ours:.2f} | "
              f"{k_theirs:.2f} | {f['er'] ** 2 / f['R']:.2e} | "
              f"{theirs['rot'] ** 2 / theirs['rotation']:.2e} | {f['profile']} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
