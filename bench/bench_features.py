"""Feature-extraction benchmarks: speed on generated plans, and (``--real``) the checks on real
data whose figures go into docs/benchmarks.md.

    .venv/bin/python bench/bench_features.py            # speed (targets: 1,500 m² ≤ 2 s,
                                                         #   10,000 m² ≤ 10 s at 0.05 m/px)
    .venv/bin/python bench/bench_features.py --real     # rooms IoU, thesis comparison, ...

``--real`` reads ../shared/data (or $SLAM_PREDICT_SHARED/data) and prints markdown tables.
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from slam_predict.features import kernels
from slam_predict.features.vector import FeaturesConfig, compute_features
from slam_predict.world.generator import generate

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("SLAM_PREDICT_SHARED", ROOT.parent / "shared"))


def bench_speed(repeats: int = 3) -> None:
    """Time the full vector of generated plans (median of ``repeats`` after one warm run)."""
    kernels.warmup()
    print("| plan | free area m² | bitmap px | full vector s (median) | target |")
    print("|---|---|---|---|---|")
    for area, target in ((1500, 2.0), (10000, 10.0)):
        for kind in ("office", "school"):
            world = generate(kind, area, 1, 0.05)
            compute_features(world)
            times = []
            for _ in range(repeats):
                start = time.perf_counter()
                compute_features(world)
                times.append(time.perf_counter() - start)
            print(f"| {kind} {area} m² seed 1 | {world.free_area_m2:.0f} | "
                  f"{world.shape[1]}×{world.shape[0]} | {statistics.median(times):.2f} | "
                  f"≤ {target:g} s |")


def bench_rooms(data: Path) -> None:
    from slam_predict.features.validation import downsampled, ipa_room_scores
    from slam_predict.features.vector import Context
    from slam_predict.world.bitmap import load_occupancy
    from slam_predict.world.model import World

    print("\n| ipa map | GT rooms | our rooms | count error | mean best-match IoU "
          "| our rooms at 0.10 m/px |")
    print("|---|---|---|---|---|---|")
    scores = []
    for path in sorted((data / "floorplans" / "ipa").glob("*.png")):
        if path.name.endswith("_gt_segmentation.png"):
            continue
        s = ipa_room_scores(str(path))
        scores.append(s)
        coarse = downsampled(World(path.name, load_occupancy(str(path)), 0.05), 0.1)
        print(f"| {s.name} | {s.truth_rooms} | {s.our_rooms} | {s.count_error:+d} | "
              f"{s.mean_iou:.3f} | {Context(coarse, FeaturesConfig()).rooms.count} |")
    print(f"| **mean** | | | {np.mean([abs(s.count_error) for s in scores]):.1f} (abs) | "
          f"**{np.mean([s.mean_iou for s in scores]):.3f}** | |")


def bench_thesis(data: Path) -> None:
    from slam_predict.features.validation import single_feature_r2, thesis_rows

    traversal = ("voronoi_traversal",)
    doc = thesis_rows(str(data), FeaturesConfig())
    compat = thesis_rows(str(data), FeaturesConfig(families=traversal,
                                                   mode="thesis_compatible"))
    coarse = thesis_rows(str(data), FeaturesConfig(), resolution=0.1)
    print("\n| building | faithful | theirs m | ours m | ratio | thesis_compatible m | ratio "
          "| ours at 0.10 m/px | 0.10 / 0.05 | rooms 0.05 / 0.10 |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    key = "voronoi_traversal_distance"
    for a, b, c in zip(doc, compat, coarse, strict=False):
        theirs = a["theirs"]["Voronoi distance"]
        print(f"| {a['env']} | {'yes' if a['faithful'] else 'no'} | {theirs:.1f} | "
              f"{a['ours'][key]:.1f} | {a['ours'][key] / theirs:.2f} | {b['ours'][key]:.1f} | "
              f"{b['ours'][key] / theirs:.2f} | {c['ours'][key]:.1f} | "
              f"{c['ours'][key] / a['ours'][key]:.3f} | "
              f"{a['ours']['num_spaces']:.0f} / {c['ours']['num_spaces']:.0f} |")
    theirs = np.array([r["theirs"]["Voronoi distance"] for r in doc])
    faithful = np.array([r["faithful"] for r in doc])
    y = np.array([r["theirs"]["transError.mean.mean"] for r in doc])
    print("\n| variant | N | Pearson r | median ours/theirs | r (faithful) | median (faithful) "
          "| single-feature R² on transError.mean.mean (median / mean of 20 splits) |")
    print("|---|---|---|---|---|---|---|")
    r2_theirs = single_feature_r2(theirs, y)
    for label, rows in (("documented", doc), ("thesis_compatible", compat),
                        ("documented at 0.10 m/px", coarse)):
        ours = np.array([r["ours"][key] for r in rows])
        r2 = single_feature_r2(ours, y)
        print(f"| {label} | {len(ours)} | {np.corrcoef(ours, theirs)[0, 1]:.3f} | "
              f"{np.median(ours / theirs):.3f} | "
              f"{np.corrcoef(ours[faithful], theirs[faithful])[0, 1]:.3f} | "
              f"{np.median(ours[faithful] / theirs[faithful]):.3f} | "
              f"{np.median(r2):.3f} / {np.mean(r2):.3f} |")
    print(f"| thesis' own Voronoi distance | {len(theirs)} | | | | | "
          f"{np.median(r2_theirs):.3f} / {np.mean(r2_theirs):.3f} |")
    ours = np.array([r["ours"][key] for r in doc])
    r2_ours_f = single_feature_r2(ours[faithful], y[faithful])
    r2_theirs_f = single_feature_r2(theirs[faithful], y[faithful])
    print(f"\nFaithful buildings only ({faithful.sum()}): R² ours {np.median(r2_ours_f):.3f} / "
          f"{np.mean(r2_ours_f):.3f}, thesis' column {np.median(r2_theirs_f):.3f} / "
          f"{np.mean(r2_theirs_f):.3f} (median / mean of 20 splits).")
    ratio = np.array([c["ours"][key] / a["ours"][key] for a, c in zip(doc, coarse, strict=False)])
    print(f"\nResolution 0.10 vs 0.05 m/px over {len(ratio)} buildings: "
          f"{np.mean(np.abs(ratio - 1) <= 0.05):.0%} within 5 %, median |Δ| "
          f"{np.median(np.abs(ratio - 1)):.1%}, worst {np.max(np.abs(ratio - 1)):.1%}.")
    delta = np.array([abs(a["ours"]["num_spaces"] - c["ours"]["num_spaces"])
                      for a, c in zip(doc, coarse, strict=False)])
    print(f"Room count 0.10 vs 0.05 m/px: equal in {int(np.sum(delta == 0))} of {len(delta)}, "
          f"within ±1 in {int(np.sum(delta <= 1))}, worst {int(delta.max())}.")


def bench_resolution_generated() -> None:
    print("\n| generated building | rooms 0.05 / 0.10 | traversal 0.05 m | 0.10 m | ratio |")
    print("|---|---|---|---|---|")
    for kind in ("office", "school"):
        for seed in range(4):
            a, b = (compute_features(generate(kind, 800, seed, res)) for res in (0.05, 0.1))
            da, db = a["voronoi_traversal_distance"], b["voronoi_traversal_distance"]
            print(f"| {kind} 800 m² seed {seed} | {a['num_spaces']:.0f} / {b['num_spaces']:.0f} "
                  f"| {da:.1f} | {db:.1f} | {db / da:.3f} |")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--real", action="store_true", help="also run the real-data checks")
    args = parser.parse_args(argv)
    bench_speed()
    if args.real:
        data = SHARED / "data"
        if not data.is_dir():
            print(f"real data not found at {data}", file=sys.stderr)
            return 1
        bench_rooms(data)
        bench_thesis(data)
        bench_resolution_generated()
    return 0


if __name__ == "__main__":
    sys.exit(main())
