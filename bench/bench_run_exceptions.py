#!/usr/bin/env python3
"""The runs of a campaign that end stuck or below coverage 0.95, with their final SLAM maps.

For each such run (``WORLD/run_NNN/`` with run.json, map.pgm/map.yaml, slam.tum and
ground_truth.tum: the run folder as collected, not only the committed run.json): coverage,
stop reason, whether it ended stuck (``slam-predict fidelity``'s rule,
``fidelity_parts.ended_stuck``) and the stuck record's longest time within its circle, how
the explorer ended, path, the online SLAM pose error (largest, and at the end: slam.tum
put on the true start, `bench_pose_jumps.online_error`), and the share of the reachable floor
the laser swept from the true poses of the processed scans (`bench_coverage_timeline`: a run
that swept the floor but whose drifted map lies beside it has a low coverage and a high
swept share). With ``--plot PNG``, two panels per run: the final SLAM map with the online
trajectory, its end marked, and the plan with the reachable floor by class
(`bench_coverage_timeline.floor_picture`: swept and in the map, swept but outside the drifted
map, never swept). docs/fidelity.md "Runs that
end stuck or short".

    python bench/bench_run_exceptions.py data/campaigns/fidelity_seed_study [--plot PNG]
"""
from __future__ import annotations

import argparse
import io
import json
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench"))

from bench_coverage_timeline import floor_picture, load_run, swept_curve  # noqa: E402
from bench_pose_jumps import online_error  # noqa: E402

from slam_predict.collect.fidelity_parts import FULL_COVERAGE, ended_stuck  # noqa: E402
from slam_predict.formats.tum import read_tum  # noqa: E402


def exception_runs(campaign: Path) -> list[Path]:
    """Run folders whose run.json is below FULL_COVERAGE or ended with the robot stuck."""
    out = []
    for path in sorted(campaign.glob("*/run_*/run.json")):
        record = json.loads(path.read_text())
        if record["coverage"] < FULL_COVERAGE or ended_stuck(record):
            out.append(path.parent)
    return out


def row(run: Path) -> dict:
    """The table row of one run (module doc)."""
    record = json.loads((run / "run.json").read_text())
    t, error = online_error(run)
    record_, world, settings, reach = load_run(run)
    _, swept = swept_curve(run, record_, world, settings, reach, record_["sim_duration_s"])
    end = record.get("explorer_end") or {}
    return {"world": record["world"], "run": run.name, "coverage": record["coverage"],
            "stop": record["stop_reason"], "sim_s": record["sim_duration_s"],
            "path_m": record["distance_m"],
            "still_s": (record.get("stuck") or {}).get("longest_still_s", math.nan),
            "stuck": ended_stuck(record),
            "explorer": f"{end['reason']} at {end['t']:.0f} s" if end else "running",
            "max_error_m": float(error.max()), "max_error_s": float(t[int(np.argmax(error))]),
            "end_error_m": float(error[-1]), "swept": float(swept[-1])}


def draw(ax, run: Path, info: dict) -> None:
    """The run's final SLAM map, cropped to its known cells, with the online trajectory."""
    import yaml
    from PIL import Image

    meta = yaml.safe_load((run / "map.yaml").read_text())
    image = np.asarray(Image.open(run / meta["image"]).convert("L"))
    res, (ox, oy) = float(meta["resolution"]), meta["origin"][:2]
    known = np.argwhere(image != 205)
    (r0, c0), (r1, c1) = known.min(axis=0), known.max(axis=0) + 1
    height = image.shape[0]
    extent = (ox + c0 * res, ox + c1 * res, oy + (height - r1) * res, oy + (height - r0) * res)
    ax.imshow(image[r0:r1, c0:c1], cmap="gray", vmin=0, vmax=255, extent=extent)
    _, pose = read_tum(run / "slam.tum")
    ax.plot(pose[:, 0], pose[:, 1], lw=0.4, color="tab:blue")
    ax.plot(*pose[-1, :2], "o", color="tab:red", ms=4)
    ax.set_title(f"{info['world'][:24]} {info['run']}\ncoverage {info['coverage']:.2f}, "
                 f"{'stuck' if info['stuck'] else info['explorer']}", fontsize=7)
    ax.set_xticks([])
    ax.set_yticks([])


def draw_floor(ax, run: Path, info: dict) -> None:
    """The plan with the run's reachable floor by class, cropped to the building."""
    image = floor_picture(run)
    inside = np.argwhere(image.min(axis=2) < 255)
    (r0, c0), (r1, c1) = inside.min(axis=0), inside.max(axis=0) + 1
    ax.imshow(image[r0:r1, c0:c1], interpolation="nearest")
    ax.set_title(f"swept {info['swept']:.2f}: green in the map, orange beside it,\n"
                 "red never swept", fontsize=7)
    ax.set_xticks([])
    ax.set_yticks([])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("campaign", type=Path)
    parser.add_argument("--plot", type=Path, help="also draw the maps to this PNG")
    args = parser.parse_args(argv)
    found = exception_runs(args.campaign)
    runs = [run for run in found if (run / "slam.tum").is_file() and (run / "map.yaml").is_file()]
    for run in sorted(set(found) - set(runs)):
        print(f"{run.parent.name}/{run.name}: its trajectories and map are not in this folder "
              "(collected elsewhere; re-run its seed to see them)")
    rows = [row(run) for run in runs]
    print("| building | run | coverage (swept) | ended stuck (longest within the circle, s) "
          "| explorer | sim s | path m | online pose error: max (at s) / end, m |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['world']} | {r['run']} | {r['coverage']:.3f} ({r['swept']:.3f}) | "
              f"{'yes' if r['stuck'] else 'no'} ({r['still_s']:.0f}) | {r['explorer']} | "
              f"{r['sim_s']:.0f} | {r['path_m']:.0f} | {r['max_error_m']:.2f} "
              f"({r['max_error_s']:.0f}) / {r['end_error_m']:.2f} |")
    if args.plot and rows:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from PIL import Image

        cols = 4
        lines = math.ceil(2 * len(rows) / cols)
        fig, axes = plt.subplots(lines, cols, figsize=(3.2 * cols, 3.0 * lines), squeeze=False)
        for ax in np.ravel(axes):
            ax.axis("off")
        pairs = np.ravel(axes).reshape(-1, 2)
        for (map_ax, floor_ax), run, info in zip(pairs, runs, rows, strict=False):
            map_ax.axis("on")
            floor_ax.axis("on")
            draw(map_ax, run, info)
            draw_floor(floor_ax, run, info)
        fig.tight_layout()
        buffer = io.BytesIO()
        fig.savefig(buffer, dpi=80)
        # 64 colours: a map figure small enough for docs/
        Image.open(buffer).convert("RGB").quantize(64).save(args.plot, optimize=True)
        print(f"maps: {args.plot}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
