"""bench/bench_odometry_signature.py on synthetic tables and run records: D_odo, the CV of ε_r
and how ε_r follows the per-run heading bias, checked against values worked out by hand."""
import json
from pathlib import Path

import pytest

COLUMNS = ("dataset, Voronoi distance, Voronoi rotation, totalLen, totalRot, transError.mean.mean, "
           "transError.mean.std, rotError.mean.mean, rotError.mean.std")



def _table(path: Path, rows) -> Path:
    lines = [COLUMNS] + [f"{name}, 1, 1, 100, {rot}, 0.1, 0.01, {er}, {er_std}"
                         for name, rot, er, er_std in rows]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def _run(folder: Path, building: str, index: int, rot_mean: float, bias_theta: float,
         coverage: float = 1.0) -> None:
    run = folder / building / f"run_{index:03d}"
    run.mkdir(parents=True)
    record = {"coverage": coverage, "metric": {"rot_mean": rot_mean},
              "odometry_error": {"model": "uniform_per_run", "bias": [0.0, 0.0, bias_theta]}}
    (run / "run.json").write_text(json.dumps(record), encoding="utf-8")


def test_theirs_d_odo_and_cv(load_bench, tmp_path):
    bench = load_bench("bench_odometry_signature")
    # D_odo = (er_R^2 - er_O^2) / totalRot: (0.02^2 - 0.01^2) / 100 = 3e-6 and
    # (0.04^2 - 0.02^2) / 300 = 4e-6, median 3.5e-6
    realistic = bench.read_stats(_table(tmp_path / "r.csv", [("a", 100, 0.02, 0.002),
                                                            ("b", 300, 0.04, 0.008)]))
    optimistic = bench.read_stats(_table(tmp_path / "o.csv", [("a", 150, 0.01, 0.004),
                                                             ("b", 500, 0.02, 0.010)]))
    cv_line, d_line = bench.theirs_summary(realistic, optimistic)
    assert "realistic median 0.15" in cv_line          # CVs 0.1 and 0.2
    assert "optimistic median 0.45" in cv_line         # CVs 0.4 and 0.5
    assert "D_odo median 3.50e-06" in d_line


def test_ours_cv_and_bias_following(load_bench, tmp_path):
    bench = load_bench("bench_odometry_signature")
    campaign = tmp_path / "camp"
    for i, (rot, bias) in enumerate([(0.01, 0.005), (0.02, -0.010), (0.03, 0.015)]):
        _run(campaign, "a", i, rot, bias)
    _run(campaign, "a", 3, 0.5, 0.0, coverage=0.2)     # a failed run, left out at 0.5
    _run(campaign, "b", 0, 0.04, 0.001)                 # one run: no CV
    line = bench.ours_summary(campaign, min_coverage=0.5)
    assert "1 buildings, 3 runs" in line
    assert "CV of ε_r median 0.50" in line             # std 0.01 / mean 0.02
    assert "Spearman(|b_θ|, ε_r / building mean) +1.00" in line


def test_missing_tables_exit_2(load_bench, tmp_path, capsys):
    bench = load_bench("bench_odometry_signature")
    assert bench.main(["--thesis-dir", str(tmp_path)]) == 2
    assert "thesis tables not found" in capsys.readouterr().err


def test_real_tables_signature(load_bench):
    bench = load_bench("bench_odometry_signature")
    thesis = bench.SHARED_DATA / "thesis"
    if not (thesis / "stats_optimistic.csv").is_file():
        pytest.skip(f"seed-study tables not found in {thesis} (../shared/data absent)")
    cv_line, d_line = bench.theirs_summary(bench.read_stats(thesis / "stats_realistic.csv"),
                                           bench.read_stats(thesis / "stats_optimistic.csv"))
    # the seed study's heading error is tight from run to run and grows as a random walk
    assert "realistic median 0.15" in cv_line
    assert "D_odo median 1.54e-06" in d_line
