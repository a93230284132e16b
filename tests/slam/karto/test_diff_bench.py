"""bench/bench_karto_diff.py's acceptance figures and median row, and run discovery for runs of
any in-loop back-end (bench/gmapping_diff/collected_runs.py), on hand-made records."""
import json


def record(indices, poses, loops, error, cpu):
    return {"indices": indices, "poses": poses, "loop_closures": loops,
            "error": {"trans_mean_m": error}, "cpu_s": cpu}


def test_agreement_and_median_row(load_bench):
    bench = load_bench("bench_karto_diff")
    real = record([0, 3, 7], [[0, 0, 0], [1, 0, 0], [2, 0, 0]], [[7, 0]], 0.2, 2.0)
    same = record([0, 3, 7], [[0, 0, 0], [1.005, 0, 0], [2, 0, 0]], [[7, 0]], 0.2, 3.0)
    off = record([0, 3, 7], [[0, 0, 0], [1.02, 0, 0], [2, 0.5, 0]], [[7, 3]], 0.3, 4.0)
    a, b = bench.agreement(same, real), bench.agreement(off, real)
    assert a["accepted_same"] and a["closures_same"] and a["within_1cm"] == 1.0
    assert a["ratio"] == 1.0 and abs(b["ratio"] - 1.5) < 1e-12
    assert b["accepted_same"] and not b["closures_same"] and abs(b["within_1cm"] - 1 / 3) < 1e-12
    row = bench.median_row([a, b, a])
    assert "3/3 same" in row and "2/3 same" in row and "| 100.0 |" in row and "| 1.00 |" in row


def test_runs_of_any_back_end_are_found(tmp_path, load_bench):
    bench = load_bench("bench_karto_diff")
    for name, backend in (("run_000", "karto"), ("run_001", "gmapping")):
        run = tmp_path / "w" / name
        run.mkdir(parents=True)
        (run / "sensors.log.gz").write_bytes(b"")
        (run / "run.json").write_text(json.dumps({"world": "w", "sensor_logs": {backend: {}}}))
    assert [p.name for p in bench.collected.find_runs([tmp_path], None)] == ["run_000", "run_001"]
    assert [p.name for p in bench.collected.find_runs([tmp_path])] == ["run_001"]
    assert bench.log_source(str(tmp_path / "w" / "run_000"))[1] == "w-run_000"
