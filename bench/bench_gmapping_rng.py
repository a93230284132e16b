"""Our GMapping port on one log with different random streams (no upstream needed).

With ``drand48`` (the port's default stream, ``slam_predict.slam.gmapping.drand48``) the port
draws the real openslam_gmapping's own noise (POSIX drand48 and ``pf_ran_gaussian``, seeded as
slam_gmapping seeds it), so its runs ARE the real library's runs (docs/gmapping.md);
``pcg64`` is ``numpy.random.default_rng(seed)`` (the ``random_stream: numpy`` option),
``mt19937`` numpy's Mersenne Twister. Same input, parameters and metric as
``bench_gmapping_diff.py`` (it is reused), so the per-seed errors are comparable.

Usage: bench/bench_gmapping_rng.py [--log aces] --rng drand48 pcg64 [--seeds 1-10 | 5,900,12345]
           [--out DIR]
Prints per generator the errors per seed (m), mean, median, share above 1 m and resamples; runs
are cached as ``<out>/<log>/<rng>_<seed>.json``.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench"))
import bench_gmapping_diff as diff  # noqa: E402

from slam_predict.slam.gmapping.drand48 import Drand48Generator  # noqa: E402

GENERATORS = {"drand48": Drand48Generator,
              "pcg64": np.random.default_rng,
              "mt19937": lambda seed: np.random.Generator(np.random.MT19937(seed))}


def run_seed(data, params, rng_name: str, seed: int) -> dict:
    """One run of our port with generator ``rng_name`` seeded by ``seed``: error and resamples."""
    record = diff.run_port(data, params, GENERATORS[rng_name](seed))  # params' stream: numpy
    record["error"] = diff.error_of(data, np.array(record["indices"]), np.array(record["poses"]))
    return {"rng": rng_name, "seed": seed, **record}


def summary(rng_name: str, runs: list) -> str:
    errors = np.array([r["error"]["trans_mean_m"] for r in runs])
    return (f"{rng_name}: n {len(errors)}, mean {errors.mean():.3f} m, median "
            f"{np.median(errors):.3f} m, above 1 m {int((errors > 1.0).sum())}/{len(errors)}, "
            f"resamples {np.mean([r['resamples'] for r in runs]):.0f}; per seed: "
            + " ".join(f"{r['seed']}:{r['error']['trans_mean_m']:.3f}" for r in runs))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--log", default="aces", help="a shared log name or a CARMEN path")
    parser.add_argument("--config", help="slam_gmapping YAML for a log given as a path")
    parser.add_argument("--rng", nargs="+", choices=sorted(GENERATORS), default=["pcg64"])
    parser.add_argument("--seeds", type=diff.seeds_arg, default=list(range(1, 4)))
    parser.add_argument("--out", default=str(ROOT / "out" / "bench_gmapping_rng"))
    args = parser.parse_args()
    data, params, short = diff.load(args.log, args.config, {})
    folder = Path(args.out) / short
    folder.mkdir(parents=True, exist_ok=True)
    for rng_name in args.rng:
        runs = []
        for seed in args.seeds:
            cache = folder / f"{rng_name}_{seed}.json"
            if not cache.exists():
                cache.write_text(json.dumps(run_seed(data, params, rng_name, seed)) + "\n")
            runs.append(json.loads(cache.read_text()))
        print(summary(rng_name, runs), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
