"""World building benchmark: procedural generator, layout XML rasterisation, thesis import.

Prints, at 0.05 m/px: generate() wall time for office/school buildings of 500–10,000 m² (one
seed each, best of ``--repeat``), its free-area error; rasterise_layout() time for every layout
XML of ../shared/data (total, mean, max); thesis_world() time for all 44 thesis buildings.
Numba kernels are warmed first. Usage: bench/bench_generator.py [--repeat 3] [--seed 0]
"""
from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("SLAM_PREDICT_SHARED", ROOT.parent / "shared")) / "data"


def best_of(repeat, fn):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
    return min(times), result


def bench_generator(repeat: int, seed: int) -> None:
    from slam_predict.world.generator import generate

    print(f"generator (best of {repeat}, seed {seed})")
    print(f"{'kind':7s} {'area m2':>8s} {'shape':>8s} {'free m2':>8s} {'err %':>6s} "
          f"{'rooms':>5s} {'cells':>11s} {'time s':>7s}")
    for area in (500.0, 1500.0, 3000.0, 6000.0, 10000.0):
        for kind in ("office", "school"):
            seconds, world = best_of(repeat,
                                     lambda kind=kind, area=area: generate(kind, area, seed))
            info = world.provenance["generator"]
            print(f"{kind:7s} {area:8.0f} {info['shape']:>8s} {world.free_area_m2:8.1f} "
                  f"{100 * (world.free_area_m2 / area - 1):+6.1f} {len(world.rooms):5d} "
                  f"{world.occupied.size:11,d} {seconds:7.2f}")


def bench_layouts() -> None:
    from slam_predict.world.layout import rasterise_layout

    files = sorted((SHARED / "floorplans" / "layouts").glob("*.xml"))
    if not files:
        print("layouts: no data")
        return
    times = []
    for path in files:
        start = time.perf_counter()
        rasterise_layout(path)
        times.append((time.perf_counter() - start, path.name))
    total = sum(t for t, _ in times)
    slowest = max(times)
    print(f"layout XML -> World (no start pose), {len(files)} files: total {total:.1f} s, "
          f"mean {total / len(files):.2f} s, max {slowest[0]:.2f} s ({slowest[1]})")


def bench_thesis() -> None:
    from slam_predict.world.thesis import read_environments, thesis_world

    csv_path = SHARED / "thesis" / "environments.csv"
    if not csv_path.is_file():
        print("thesis: no data")
        return
    envs = read_environments(csv_path)
    start = time.perf_counter()
    total_area = sum(thesis_world(env)[0].free_area_m2 for env in envs)
    print(f"thesis worlds ({len(envs)} buildings, incl. start pose): "
          f"{time.perf_counter() - start:.1f} s, free area total {total_area:,.0f} m²")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    import logging

    logging.disable(logging.WARNING)
    from slam_predict.world import raster
    raster.warmup()
    bench_generator(args.repeat, args.seed)
    bench_layouts()
    bench_thesis()


if __name__ == "__main__":
    main()
