"""Peak memory per image pixel of ``slam-predict features`` on large generated plans: the
figure behind ``world.bitmap.BYTES_PER_PIXEL`` (the size guard's memory estimate).

    .venv/bin/python bench/bench_plan_memory.py [--sizes 2000 4000 6000]

Each plan is a generated office (``world.generator``) written as a PNG at a resolution chosen so
that the building keeps ~10,000 m² whatever the pixel count; every run is a separate process
(``--max-pixels`` raised), its peak RSS read from ``getrusage(RUSAGE_CHILDREN)``.
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import cv2
import numpy as np

from slam_predict.world.generator import generate

ROOT = Path(__file__).resolve().parents[1]


def plan_png(folder: Path, side_px: int) -> tuple:
    """(path, resolution m/px) of a ~10,000 m² office resampled to ``side_px`` on its long side."""
    world = generate("office", 10000, 1, 0.1)
    rows, cols = world.occupied.shape
    scale = side_px / max(rows, cols)
    size = (max(1, round(cols * scale)), max(1, round(rows * scale)))
    image = np.where(world.occupied, 0, 255).astype(np.uint8)
    image = cv2.resize(image, size, interpolation=cv2.INTER_NEAREST)
    path = folder / f"office_{side_px}.png"
    cv2.imwrite(str(path), image)
    return path, world.resolution / scale, size[0] * size[1]


def peak_rss_bytes(argv) -> tuple:
    """(peak RSS in bytes, wall time s) of one child process; each call measures a fresh child
    because RUSAGE_CHILDREN reports the maximum over the children waited for so far."""
    start = time.monotonic()
    code = (f"import resource, subprocess, sys; subprocess.run({argv!r}, check=True, "
            "stdout=subprocess.DEVNULL); print(resource.getrusage(resource.RUSAGE_CHILDREN)"
            ".ru_maxrss)")
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True,
                         text=True, env=dict(os.environ))
    return int(out.stdout.split()[-1]) * 1024, time.monotonic() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[2000, 4000, 6000])
    args = parser.parse_args()
    print("| image px | resolution m/px | peak RSS GB | bytes / px | time s |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for side in args.sizes:
            path, res, pixels = plan_png(Path(tmp), side)
            argv = [sys.executable, "-m", "slam_predict.cli.main", "features", str(path),
                    "--resolution", f"{res:.6f}", "--json", "--max-pixels", str(pixels + 1)]
            rss, seconds = peak_rss_bytes(argv)
            print(f"| {pixels / 1e6:.1f} M | {res:.4f} | {rss / 1e9:.2f} | {rss / pixels:.0f} "
                  f"| {seconds:.0f} |", flush=True)


if __name__ == "__main__":
    main()
