"""bench/bench_gmapping_diff.py's summary (no upstream needed): ratio of means, bootstrap
interval, flagging of differing processed scans."""
import importlib.util
from pathlib import Path

import numpy as np

BENCH = Path(__file__).resolve().parents[2] / "bench" / "bench_gmapping_diff.py"


def _bench():
    spec = importlib.util.spec_from_file_location("bench_gmapping_diff", BENCH)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _record(side, seed, error, indices=(0, 2, 5)):
    return {"side": side, "seed": seed, "log": "x", "indices": list(indices),
            "poses": [[float(k), 0.0, 0.0] for k in indices],
            "error": {"trans_mean_m": error}, "resamples": 3, "neff": [20.0, 10.0], "cpu_s": 1.0}


def test_ratio_and_interval():
    bench = _bench()
    records = [_record("ours", s, e) for s, e in enumerate([0.2, 0.3, 0.4])]
    records += [_record("real", s, e) for s, e in enumerate([0.25, 0.25, 0.25])]
    row = bench.table(records).splitlines()[2].split(" | ")
    assert row[1] == "3" and row[2] == "3/3"
    assert row[3:6] == ["0.300", "0.300", "0.200–0.400"]
    assert row[9] == "1.20"
    lo, hi = (float(v) for v in row[10].split("–"))
    assert 0.8 <= lo < 1.2 < hi <= 1.6
    lo, hi = bench.bootstrap_ratio(np.array([1.0, 1.0]), np.array([2.0, 2.0]))
    assert lo == hi == 0.5


def test_position_differences_per_seed():
    bench = _bench()
    records = [_record("ours", 1, 0.2), _record("real", 1, 0.2), _record("ours", 2, 0.2),
               _record("real", 2, 0.2, indices=(0, 3, 5))]
    for r, dx in zip(records, (0.0, 3e-4, 0.0, 0.0), strict=True):
        r["poses"] = [[dx, 0.0, 0.0], [1.0, 2.0, 0.1], [2.0, 2.0 + 4 * dx, 0.2]]
    assert bench.pose_differences(records) == [(1, "1.2e-03"), (2, "scans differ")]
    assert "max position difference ours − real per seed (m): 1:1.2e-03 2:scans differ" \
        in bench.table(records)


def test_differing_processed_scans_are_flagged():
    bench = _bench()
    records = [_record("ours", 1, 0.2), _record("real", 1, 0.2, indices=(0, 3, 5))]
    assert "(scans differ)" in bench.table(records)
    records[1]["indices"] = [0, 2, 5]
    assert "(scans differ)" not in bench.table(records)


def test_rng_bench_generators_and_summary():
    spec = importlib.util.spec_from_file_location(
        "bench_gmapping_rng", BENCH.parent / "bench_gmapping_rng.py")
    rng_bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(rng_bench)
    draws = {name: make(7).random() for name, make in rng_bench.GENERATORS.items()}
    assert draws["pcg64"] == np.random.default_rng(7).random()
    assert draws["mt19937"] == np.random.Generator(np.random.MT19937(7)).random()
    assert len(set(draws.values())) == 3
    runs = [{"seed": s, "error": {"trans_mean_m": e}, "resamples": r}
            for s, e, r in ((1, 0.5, 10), (2, 1.5, 20), (3, 0.7, 30))]
    assert rng_bench.summary("pcg64", runs) == (
        "pcg64: n 3, mean 0.900 m, median 0.700 m, above 1 m 1/3, resamples 20; "
        "per seed: 1:0.500 2:1.500 3:0.700")
