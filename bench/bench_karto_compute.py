#!/usr/bin/env python3
"""What the real Karto (slam_toolbox e38048f) spends per Mapper::Process call and per map
rebuild (CPU s), from the real library's outputs on the shared SLAM logs: the calibration of the
async node's busy-time model (``scan_gate: async``, src/slam_predict/slam/karto/realtime.py,
config/karto.yaml, docs/karto.md "Async real time").

Input: the ``real.json`` files of the karto_real driver (``$SLAM_PREDICT_KARTO_REF`` or
../karto_ref beside the project; README.md there): ``process_cpu_s`` (CPU s of every Process
call), ``accepted`` (the scans added), ``loop_closures`` (closing scan of each edge) and
``grid_cpu`` (CPU s of OccupancyGrid::CreateFromScans at four points of the run). Both gates
(``<log>/`` sync, ``gate_none/<log>/``) of every log are pooled.

Least-squares fits printed (coefficients ≥ 0):

* accepted call = ``process_s`` + ``process_s_per_beam`` × beams
  + [closing call] (``closure_s_per_beam`` × beams + ``closure_s_per_node`` × scans in graph);
* rejected call (HasMovedEnough false) = ``rejected_s`` (the mean);
* rebuild = ``map_s_per_cell`` × grid cells + ``map_s_per_beam`` × beams of the scans in it.

Then per log and gate: the measured CPU of all Process calls and the model's (ratio), the same
for the four rebuilds.

Usage: bench/bench_karto_compute.py [--ref DIR]
"""
from __future__ import annotations

import argparse
import json
import os
from pathlib import Path

import numpy as np
from scipy.optimize import nnls

ROOT = Path(__file__).resolve().parents[1]
LOGS = ("intel", "aces", "csail", "freiburg-101", "freiburg-079")
PROCESS_KEYS = ("process_s", "process_s_per_beam", "closure_s_per_beam", "closure_s_per_node")
MAP_KEYS = ("map_s_per_cell", "map_s_per_beam")


def reference_dir() -> Path:
    """$SLAM_PREDICT_KARTO_REF, else ../karto_ref beside the project."""
    return Path(os.environ.get("SLAM_PREDICT_KARTO_REF", ROOT.parent / "karto_ref"))


def beams_of(folder: Path) -> int:
    """Beams of the log's laser (the ``angles N ...`` line of scans.txt)."""
    with open(folder / "scans.txt") as handle:
        for line in handle:
            if line.startswith("angles"):
                return int(line.split()[1])
    raise ValueError(f"{folder / 'scans.txt'}: no angles line")


def process_rows(real: dict, beams: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(design rows of accepted calls (n, 4), their CPU s (n,), CPU s of rejected calls)."""
    order = {a[0]: k for k, a in enumerate(real["accepted"])}
    closing = {c[0] for c in real["loop_closures"]}
    rows, costs, rejected = [], [], []
    for index, cpu in real["process_cpu_s"]:
        if index not in order:
            rejected.append(cpu)
            continue
        closes = float(index in closing)
        rows.append((1.0, beams, closes * beams, closes * order[index]))
        costs.append(cpu)
    return np.array(rows, float).reshape(-1, 4), np.array(costs, float), np.array(rejected)


def map_rows(real: dict, beams: int) -> tuple[np.ndarray, np.ndarray]:
    """(design rows (cells, beams in the map) of the timed rebuilds, their CPU s)."""
    grid = real["grid_cpu"]
    rows = [(g["cells"], g["accepted"] * beams) for g in grid]
    return np.array(rows, float), np.array([g["cpu_s"] for g in grid], float)


def load(ref: Path) -> list[dict]:
    """Every (log, gate) of the reference folder that has a real.json."""
    runs = []
    for gate, base in (("sync", ref), ("none", ref / "gate_none")):
        for log in LOGS:
            folder = base / log
            if not (folder / "real.json").is_file():
                continue
            real = json.loads((folder / "real.json").read_text())
            beams = beams_of(folder)
            runs.append({"log": log, "gate": gate, "beams": beams,
                         "process": process_rows(real, beams), "map": map_rows(real, beams)})
    return runs


def fit(runs: list[dict]) -> dict[str, float]:
    """The cost model's coefficients from every run pooled (non-negative least squares)."""
    design = np.vstack([r["process"][0] for r in runs])
    costs = np.concatenate([r["process"][1] for r in runs])
    process, _ = nnls(design, costs)
    rejected = np.concatenate([r["process"][2] for r in runs])
    map_design = np.vstack([r["map"][0] for r in runs])
    map_costs = np.concatenate([r["map"][1] for r in runs])
    grid, _ = nnls(map_design, map_costs)
    model = dict(zip(PROCESS_KEYS, process.tolist(), strict=True))
    model["rejected_s"] = float(rejected.mean()) if rejected.size else 0.0
    model.update(zip(MAP_KEYS, grid.tolist(), strict=True))
    return model


def check(runs: list[dict], model: dict[str, float]) -> list[str]:
    """Per run: measured and modelled CPU s of all Process calls and of the four rebuilds."""
    process = np.array([model[k] for k in PROCESS_KEYS])
    grid = np.array([model[k] for k in MAP_KEYS])
    lines = [f"{'log':14s} {'gate':5s} {'beams':>5s} {'process real':>13s} {'model':>7s} "
             f"{'ratio':>6s} {'rebuilds real':>14s} {'model':>7s} {'ratio':>6s}"]
    for r in runs:
        design, costs, rejected = r["process"]
        real_p = costs.sum() + rejected.sum()
        model_p = (design @ process).sum() + model["rejected_s"] * rejected.size
        real_m, model_m = r["map"][1].sum(), (r["map"][0] @ grid).sum()
        lines.append(f"{r['log']:14s} {r['gate']:5s} {r['beams']:5d} {real_p:13.3f} "
                     f"{model_p:7.3f} {model_p / real_p:6.2f} {real_m:14.4f} {model_m:7.4f} "
                     f"{model_m / real_m:6.2f}")
    return lines


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--ref", type=Path, default=reference_dir(),
                        help="folder of the karto_real outputs (default %(default)s)")
    args = parser.parse_args()
    runs = load(args.ref)
    if not runs:
        parser.error(f"no <log>/real.json under {args.ref}")
    model = fit(runs)
    print("\n".join(check(runs, model)))
    print(f"\nmodel (CPU s, {len(runs)} runs of {args.ref}):")
    for key, value in model.items():
        print(f"{key}: {value:.4g}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
