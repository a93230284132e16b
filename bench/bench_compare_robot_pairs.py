#!/usr/bin/env python3
"""`predict --compare` with robot-aware models, scored on held-out (building, robot) pairs.

Input: two `slam-predict learn evaluate --runs ...` output folders, one of GMapping campaigns
and one of Karto campaigns of the same chain (e.g. Karto's with ``min_coverage: 0.95``, the
explorations that succeed). Each folder's points.csv holds the measured mean ε_t per (building,
robot configuration) and robots_predictions.csv the held-out predictions of every model kind
per protocol (buildings, configurations or both held out). For every pair measured with both
algorithms, the held-out ε_t predictions of each folder's best model (best.json) are turned into
the call `predict --compare` makes (:func:`slam_predict.learn.compare.decide`); the share of
calls that name the measured better algorithm, name the other or say "too close to call" is
printed for all pairs and for those whose measured means differ by more than ``--min-difference``
(relative to the lower).

    python bench/bench_compare_robot_pairs.py GMAPPING_EVAL KARTO_EVAL [--protocol both]
"""
from __future__ import annotations

import argparse
import csv
import json
import sys
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from slam_predict.learn.compare import DECIDING_COMPONENT, decide  # noqa: E402

CONFIDENCE = 0.9    # the robot-aware evaluation's interval level (config/robot_learning.yaml)


def measured(folder: Path) -> dict[tuple[str, str], float]:
    """{(building, robot configuration): measured mean ε_t, m}."""
    with open(folder / "points.csv", newline="") as handle:
        return {(r["world"], r["robot"]): float(r[DECIDING_COMPONENT])
                for r in csv.DictReader(handle)}


def held_out(folder: Path, protocol: str) -> tuple[str, dict[tuple[str, str], list[dict]]]:
    """The best ε_t model's kind and its held-out predictions per pair (one per repeat), as
    `predict`'s entries (status, value, low, high)."""
    best = json.loads((folder / "best.json").read_text())["best"][DECIDING_COMPONENT]
    out: dict[tuple[str, str], list[dict]] = defaultdict(list)
    with open(folder / "robots_predictions.csv", newline="") as handle:
        for r in csv.DictReader(handle):
            if (r["component"], r["model"], r["protocol"]) == (DECIDING_COMPONENT, best,
                                                                protocol):
                value = float(r["prediction"])
                out[(r["world"], r["config"])].append(
                    {"status": "ok", "value": value, "low": min(float(r["low"]), value),
                     "high": max(float(r["high"]), value)})
    return best, out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("gmapping", type=Path)
    parser.add_argument("karto", type=Path)
    parser.add_argument("--protocol", default="both", choices=("buildings", "configs", "both"))
    parser.add_argument("--min-difference", type=float, default=0.2)
    args = parser.parse_args(argv)
    truth_g, truth_k = measured(args.gmapping), measured(args.karto)
    best_g, pred_g = held_out(args.gmapping, args.protocol)
    best_k, pred_k = held_out(args.karto, args.protocol)
    calls = []   # (pair differs by more than min-difference, measured better, verdict)
    for pair in sorted(set(truth_g) & set(truth_k) & set(pred_g) & set(pred_k)):
        g, k = truth_g[pair], truth_k[pair]
        better = "karto" if k < g else "gmapping"
        differs = max(g, k) / min(g, k) > 1.0 + args.min_difference
        for entry_g, entry_k in zip(pred_g[pair], pred_k[pair], strict=False):
            decision = decide("gmapping", "karto", {"gmapping": entry_g, "karto": entry_k},
                              {"gmapping": CONFIDENCE, "karto": CONFIDENCE})
            calls.append((differs, better, decision["verdict"]))
    print(f"protocol {args.protocol}; best ε_t models: GMapping {best_g}, Karto {best_k}")
    for label, subset in (("all pairs", calls),
                          (f"measured means differ > {args.min_difference:.0%}",
                           [c for c in calls if c[0]])):
        n = len(subset)
        if not n:
            continue
        right = sum(v == b for _, b, v in subset)
        close = sum(v == "too_close_to_call" for _, _, v in subset)
        karto = sum(b == "karto" for _, b, _ in subset)
        print(f"- {label}: {n} held-out calls (Karto measured lower in {karto}): right "
              f"{right / n:.0%}, wrong {(n - right - close) / n:.0%}, too close to call "
              f"{close / n:.0%}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
