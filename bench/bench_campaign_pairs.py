#!/usr/bin/env python3
"""Two campaigns' runs of the same seeds, side by side: which repeat, which differ, by how much.

A campaign collected again with changed code and the same base seed draws the same run seeds,
so every run the change does not reach repeats its old record to the last digit. For each run
present in both folders (``WORLD/run_NNN/run.json``, same seed required) this prints the old
and new path (m), coverage, stop reason and mean ε_t (m), and whether the run repeated
(distance, rotation, coverage, sim time and both mean errors equal); then how many repeated,
the runs that ended stuck or below coverage 0.95 in each, and the median of new ÷ old ε_t and
path over the runs that differ.

    python bench/bench_campaign_pairs.py data/campaigns/fidelity_seed_study \\
        data/campaigns/fidelity_seed_study_2
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
from collections.abc import Sequence
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from slam_predict.collect.fidelity_parts import FULL_COVERAGE, ended_stuck  # noqa: E402

SAME_KEYS = ("distance_m", "rotation_rad", "coverage", "sim_duration_s")


def records(campaign: Path) -> dict[tuple[str, str], dict]:
    """{(world, run folder): run.json} of a campaign folder."""
    return {(p.parent.parent.name, p.parent.name): json.loads(p.read_text())
            for p in sorted(campaign.glob("*/run_*/run.json"))}


def metric(record: dict, key: str) -> float | None:
    """A mean error of a run, None when the run has no metric."""
    return (record.get("metric") or {}).get(key)


def repeated(old: dict, new: dict) -> bool:
    """The new run is the old one: same path, rotation, coverage, duration and mean errors."""
    return (all(old[k] == new[k] for k in SAME_KEYS)
            and all(metric(old, k) == metric(new, k) for k in ("trans_mean", "rot_mean")))


def exceptional(record: dict) -> bool:
    """Ended stuck or below FULL_COVERAGE (the rule of ``slam-predict fidelity``)."""
    return record["coverage"] < FULL_COVERAGE or ended_stuck(record)


def fmt(value: float | None, digits: int) -> str:
    """A number, or '-' for None."""
    return "-" if value is None else f"{value:.{digits}f}"


def main(argv: Sequence[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("old", type=Path, help="campaign folder collected first")
    parser.add_argument("new", type=Path, help="campaign folder collected with changed code")
    args = parser.parse_args(argv)
    old, new = records(args.old), records(args.new)
    pairs = [key for key in new if key in old]
    if not pairs:
        print(f"no run of {args.new} is in {args.old}", file=sys.stderr)
        return 2
    print("| world | run | path m old / new | coverage old / new | stop old / new "
          "| ε_t m old / new | repeated |")
    print("|---|---|---|---|---|---|---|")
    same, trans_ratio, path_ratio = 0, [], []
    for key in pairs:
        a, b = old[key], new[key]
        if a["seed"] != b["seed"]:
            print(f"{key[0]}/{key[1]}: seeds differ ({a['seed']}, {b['seed']})", file=sys.stderr)
            return 2
        is_same = repeated(a, b)
        same += is_same
        ta, tb = metric(a, "trans_mean"), metric(b, "trans_mean")
        if not is_same and ta and tb:
            trans_ratio.append(tb / ta)
            path_ratio.append(b["distance_m"] / a["distance_m"])
        print(f"| {key[0]} | {key[1]} | {a['distance_m']:.0f} / {b['distance_m']:.0f} "
              f"| {a['coverage']:.3f} / {b['coverage']:.3f} "
              f"| {a['stop_reason']} / {b['stop_reason']} | {fmt(ta, 3)} / {fmt(tb, 3)} "
              f"| {'yes' if is_same else 'no'} |")
    print(f"\n{len(pairs)} runs in both; {same} repeated, {len(pairs) - same} differ")
    for name, recs in (("old", old), ("new", new)):
        bad = [f"{w}/{r}" for (w, r) in pairs if exceptional(recs[(w, r)])]
        print(f"{name}: {len(bad)} stuck or below coverage {FULL_COVERAGE}: {', '.join(bad)}")
    if trans_ratio:
        print(f"runs that differ: median new ÷ old ε_t {statistics.median(trans_ratio):.2f}, "
              f"path {statistics.median(path_ratio):.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
