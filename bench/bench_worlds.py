"""Benchmark world I/O: load every ipa map, write + re-read it as a Stage world, render one.

Prints one line per step with wall times (best of ``--repeat``). Needs ../shared/data (or
SLAM_PREDICT_SHARED); without it only the synthetic large-world figures are printed.
"""
from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from slam_predict.world.load import load_plan
from slam_predict.world.model import World
from slam_predict.world.render import render_world
from slam_predict.world.stagefile import read_world, write_world

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("SLAM_PREDICT_SHARED", ROOT.parent / "shared")) / "data"


def best_of(repeat: int, fn):
    """(best wall time in s, last result) of ``repeat`` calls of ``fn``."""
    times, result = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
    return min(times), result


def big_world(cells: int) -> World:
    """A cells x cells office-like grid: rooms of 4 m at 0.05 m/px with doors."""
    occ = np.zeros((cells, cells), bool)
    occ[::80, :] = True
    occ[:, ::80] = True
    occ[40::80, :] = False
    occ[:, 40::80] = False
    occ[[0, -1], :] = True
    occ[:, [0, -1]] = True
    return World(name=f"grid{cells}", occupied=occ, resolution=0.05,
                 start_pose=np.array([1.0, 1.0, 0.0]))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        maps = sorted(p for p in (SHARED / "floorplans" / "ipa").glob("*.png")
                      if "gt_segmentation" not in p.name) if SHARED.is_dir() else []
        total_load = total_write = total_read = 0.0
        for path in maps:
            t_load, world = best_of(args.repeat, lambda path=path: load_plan(path, resolution=0.05))
            out = tmp / f"{path.stem}.world"
            t_write, _ = best_of(args.repeat, lambda world=world, out=out: write_world(world, out))
            t_read, _ = best_of(args.repeat, lambda out=out: read_world(out))
            total_load, total_write, total_read = (total_load + t_load, total_write + t_write,
                                                   total_read + t_read)
            rows, cols = world.shape
            print(f"{path.stem:18s} {cols:5d} x {rows:4d} px  load_plan {t_load * 1e3:6.1f} ms  "
                  f"write_world {t_write * 1e3:6.1f} ms  read_world {t_read * 1e3:6.1f} ms")
        if maps:
            print(f"all {len(maps)} ipa maps: load_plan {total_load:.2f} s, write_world "
                  f"{total_write:.2f} s, read_world {total_read:.2f} s")
            t_render, _ = best_of(1, lambda: render_world(world, tmp / "show.png"))
            print(f"render_world {maps[-1].stem} (150 dpi PNG): {t_render:.2f} s")
        for cells in (2000, 4000):
            world = big_world(cells)
            out = tmp / f"{world.name}.world"
            t_write, _ = best_of(args.repeat, lambda world=world, out=out: write_world(world, out))
            t_read, _ = best_of(args.repeat, lambda out=out: read_world(out))
            print(f"{world.name}: {cells} x {cells} px ({cells * 0.05:.0f} m square)  "
                  f"write_world {t_write:.2f} s  read_world {t_read:.2f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
