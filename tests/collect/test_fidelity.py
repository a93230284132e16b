"""Fidelity comparison: campaign summaries vs the thesis table."""
import json

import numpy as np
import pytest
from scipy.stats import spearmanr

from slam_predict.cli.main import main
from slam_predict.collect.fidelity import (
    ACCEPTANCE,
    acceptance_lines,
    compare_campaign,
    read_thesis_table,
)

THESIS_HEADER = ("dataset, Voronoi distance, Voronoi rotation, totalLen, totalRot, "
                 "transError.mean.mean, transError.mean.std, "
                 "rotError.mean.mean, rotError.mean.std\n")


def fake_campaign(root, per_world, areas=None):
    """run.json files with the fields the summary reads; per_world: name -> list of trans;
    areas: name -> free area (m²) recorded in each run.json."""
    areas = areas or {}
    for world, values in per_world.items():
        for i, trans in enumerate(values):
            folder = root / world / f"run_{i:03d}"
            folder.mkdir(parents=True)
            metric = {"trans_mean": trans, "rot_mean": trans / 10, "trans_sqr_mean": trans ** 2,
                      "rot_sqr_mean": (trans / 10) ** 2}
            (folder / "run.json").write_text(json.dumps(
                {"metric": metric, "distance_m": 100.0 * trans, "rotation_rad": 5.0,
                 "coverage": 1.0, "sim_duration_s": 1200.0,
                 "free_area_m2": areas.get(world)}))
    return root


@pytest.fixture
def tables(tmp_path):
    thesis = tmp_path / "stats.csv"
    theirs = {"a": 0.1, "b": 0.2, "c": 0.3, "d": 0.4}
    thesis.write_text(THESIS_HEADER + "".join(
        f"{w}, 1, 1, {50.0}, 1, {v}, 0.01, {v / 5}, 0.001\n" for w, v in theirs.items()))
    ours = {"a": [0.1, 0.14], "b": [0.5, 0.3], "c": [0.3, 0.34], "d": [0.9, 0.7], "own": [0.2]}
    areas = {"a": 100.0, "b": 400.0, "c": 300.0, "d": 200.0, "own": 50.0}
    return fake_campaign(tmp_path / "camp", ours, areas), thesis, theirs, ours


def test_comparison_against_a_hand_computation(tables):
    camp, thesis, theirs, ours = tables
    c = compare_campaign(camp, read_thesis_table(thesis))
    assert [r["world"] for r in c.rows] == ["a", "b", "c", "d"] and c.runs == 8
    mine = np.array([np.mean(ours[w]) for w in "abcd"])
    other = np.array([theirs[w] for w in "abcd"])
    assert c.median_ratio("trans_mean") == pytest.approx(np.median(mine / other))
    assert c.spearman("trans_mean") == pytest.approx(spearmanr(mine, other)[0])
    assert c.spearman("trans_mean") == pytest.approx(0.8)   # ranks 1,3,2,4 vs 1,2,3,4
    assert c.median_ratio("rot_mean") == pytest.approx(np.median((mine / 10) / (other / 5)))
    assert c.median_ratio("path_length_mean") == pytest.approx(np.median(100 * mine / 50))


def test_min_runs_and_cli_markdown(tables, tmp_path, capsys):
    camp, thesis, *_ = tables
    assert len(compare_campaign(camp, read_thesis_table(thesis), min_runs=3).rows) == 0
    out = tmp_path / "fidelity.md"
    assert main(["fidelity", str(camp), "--thesis", str(thesis), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "| camp | 4 | 8 | 0.80 |" in text and out.read_text() == text


def test_bad_inputs_are_one_line_errors(tables, tmp_path, capsys):
    camp, thesis, *_ = tables
    bad = tmp_path / "bad.csv"
    bad.write_text("a,b\n1,2\n")
    for argv in (["fidelity", str(camp), "--thesis", str(bad)],
                 ["fidelity", str(tmp_path / "none"), "--thesis", str(thesis)],
                 ["fidelity", str(camp), "--thesis", str(tmp_path / "missing.csv")],
                 ["fidelity", str(camp), "--thesis", str(thesis), "--min-coverage", "1.5"]):
        assert main(argv) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1, err


def test_size_trend_and_acceptance_bars_against_a_hand_computation(tables):
    camp, thesis, theirs, ours = tables
    c = compare_campaign(camp, read_thesis_table(thesis))
    ratios = [np.mean(ours[w]) / theirs[w] for w in "abcd"]     # 1.2, 2.0, 1.066.., 2.0
    assert c.size_trend() == pytest.approx(spearmanr(ratios, [100, 400, 300, 200])[0])
    lines = acceptance_lines(c)
    assert len(lines) == len(ACCEPTANCE) == 5
    assert lines[0].startswith("- ε_t Spearman ≥ 0.85: 0.80 [95 % ")
    assert lines[0].endswith("] (FAIL)")
    assert f": {np.median(ratios):.2f} [95 % " in lines[1]                 # 1.60
    # the path ratio: ours 100·ε_t m against 50 m
    path = np.median([100 * np.mean(ours[w]) / 50.0 for w in "abcd"])
    assert f": {path:.2f} [95 % " in lines[3] and lines[3].endswith("(FAIL)")


def test_size_trend_needs_areas(tmp_path):
    thesis = tmp_path / "stats.csv"
    thesis.write_text(THESIS_HEADER + "".join(f"{w}, 1, 1, 50, 1, 0.1, 0.01, 0.02, 0.001\n"
                                              for w in "abc"))
    camp = fake_campaign(tmp_path / "camp", {w: [0.1] for w in "abc"})
    assert np.isnan(compare_campaign(camp, read_thesis_table(thesis)).size_trend())


def test_plot_is_written(tables, tmp_path):
    camp, thesis, *_ = tables
    png = tmp_path / "ratio.png"
    assert main(["fidelity", str(camp), "--thesis", str(thesis), "--plot", str(png)]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 5000


def exhaustive_median_ratio_draws(c) -> np.ndarray:
    """Every equally likely outcome of one bootstrap draw of the ε_t median ratio (buildings
    drawn with replacement, then each drawn building's runs with replacement), enumerated."""
    import itertools
    per_building = []
    for row in c.rows:
        runs = c.per_run[row["world"]]["trans_mean"]
        means = [np.mean(runs[list(p)]) for p in
                 itertools.product(range(len(runs)), repeat=len(runs))]
        per_building.append([m / row["trans_mean_theirs"] for m in means])
    n = len(c.rows)
    out = []
    for pick in itertools.product(range(n), repeat=n):
        for choice in itertools.product(*(per_building[i] for i in pick)):
            out.append(np.median(choice))
    return np.array(out)


def test_bootstrap_interval_matches_the_enumerated_distribution(tmp_path):
    from slam_predict.collect.fidelity import bootstrap_intervals
    thesis = tmp_path / "stats.csv"
    theirs = {"a": 0.1, "b": 0.2, "c": 0.3}
    thesis.write_text(THESIS_HEADER + "".join(
        f"{w}, 1, 1, 50, 1, {v}, 0.01, {v / 5}, 0.001\n" for w, v in theirs.items()))
    camp = fake_campaign(tmp_path / "camp", {"a": [0.1, 0.2], "b": [0.15, 0.3], "c": [0.3]},
                         {"a": 100.0, "b": 200.0, "c": 300.0})
    c = compare_campaign(camp, read_thesis_table(thesis))
    bar = ACCEPTANCE[1]                                    # ε_t median ratio
    low, high = bootstrap_intervals(c, [bar], draws=20000, seed=3)[bar.label]
    exact = exhaustive_median_ratio_draws(c)               # a discrete distribution:
    assert np.quantile(exact, 0.015) <= low <= np.quantile(exact, 0.035)   # quantiles ± 1 %
    assert np.quantile(exact, 0.965) <= high <= np.quantile(exact, 0.985)
    assert low < high
    again = bootstrap_intervals(c, [bar], draws=20000, seed=3)[bar.label]
    assert again == (low, high)                            # seeded: same draws, same interval


def test_bootstrap_tells_a_real_size_trend_from_scatter(tmp_path):
    from slam_predict.collect.fidelity import bootstrap_intervals
    rng = np.random.default_rng(0)
    names = [f"w{i}" for i in range(16)]
    areas = {w: 100.0 * (i + 1) for i, w in enumerate(names)}
    thesis = tmp_path / "stats.csv"
    thesis.write_text(THESIS_HEADER + "".join(
        f"{w}, 1, 1, 50, 1, 0.2, 0.01, 0.04, 0.001\n" for w in names))
    trend = {w: list(0.2 * (1.5 - i / 16) * rng.uniform(0.97, 1.03, 3))
             for i, w in enumerate(names)}
    shuffled = [8, 1, 14, 5, 11, 3, 15, 0, 9, 6, 12, 2, 13, 7, 4, 10]   # ρ with area 0.04
    noise = {w: list(0.2 * (0.7 + shuffled[i] / 25) * rng.uniform(0.8, 1.2, 3))
             for i, w in enumerate(names)}
    bar = ACCEPTANCE[4]
    for name, runs, real in (("trend", trend, True), ("noise", noise, False)):
        c = compare_campaign(fake_campaign(tmp_path / name, runs, areas),
                             read_thesis_table(thesis))
        low, high = bootstrap_intervals(c, [bar], draws=500, seed=1)[bar.label]
        assert (high < -0.3) == real and (low < 0 < high) != real


def test_runs_below_min_coverage_are_left_out(tables, capsys):
    camp, thesis, theirs, ours = tables
    failed = camp / "b" / "run_001" / "run.json"          # b's second run (0.3 m) failed
    record = json.loads(failed.read_text())
    failed.write_text(json.dumps({**record, "coverage": 0.37}))
    table = read_thesis_table(thesis)
    assert compare_campaign(camp, table, min_coverage=0.0).runs == 8
    assert compare_campaign(camp, table).runs == 7              # the failed-exploration rule
    kept = compare_campaign(camp, table, min_coverage=0.5)
    row = {r["world"]: r for r in kept.rows}["b"]
    assert kept.runs == 7 and row["runs"] == 1 and row["trans_mean_ours"] == pytest.approx(0.5)
    assert list(kept.per_run["b"]["trans_mean"]) == [0.5]
    assert compare_campaign(camp, table, min_coverage=0.38, min_runs=2).runs == 6   # b dropped
    assert main(["fidelity", str(camp), "--thesis", str(thesis), "--min-coverage", "0.5"]) == 0
    assert "| camp | 4 | 7 |" in capsys.readouterr().out


def test_run_to_run_scatter_against_a_hand_computation(tables, capsys):
    camp, thesis, theirs, ours = tables
    c = compare_campaign(camp, read_thesis_table(thesis))
    # theirs: transError.mean.std 0.01 and rotError.mean.std 0.001 for every building
    mine = [np.std(ours[w], ddof=1) for w in "abcd"]      # 0.028, 0.141, 0.028, 0.141
    assert c.median_ratio("trans_std") == pytest.approx(np.median(mine) / 0.01)
    assert c.median_ratio("rot_std") == pytest.approx(np.median(mine) / 10 / 0.001)
    assert main(["fidelity", str(camp), "--thesis", str(thesis)]) == 0
    summary = capsys.readouterr().out.splitlines()[2]
    assert summary.endswith(f"| {np.median(mine) / 0.01:.2f} | {np.median(mine) / 0.01:.2f} |")


def test_scatter_of_a_single_run_is_left_out(tmp_path):
    thesis = tmp_path / "stats.csv"
    thesis.write_text(THESIS_HEADER + "".join(f"{w}, 1, 1, 50, 1, 0.1, 0.02, 0.02, 0.001\n"
                                              for w in "abc"))
    camp = fake_campaign(tmp_path / "camp", {"a": [0.1], "b": [0.1, 0.14], "c": [0.2]})
    c = compare_campaign(camp, read_thesis_table(thesis))
    assert np.isnan(c.rows[0]["trans_std_ours"])
    assert c.median_ratio("trans_std") == pytest.approx(np.std([0.1, 0.14], ddof=1) / 0.02)


def test_area_ticks_stay_within_the_plotted_areas():
    """Fixed ticks widened a small campaign's axis to 5,000 m²; a campaign's own range only."""
    import numpy as np

    from slam_predict.report.fidelity_plot import _area_ticks

    assert _area_ticks(np.array([333.0, 878.0])) == [300, 500, 1000]   # at most 15 % wider
    assert _area_ticks(np.array([333.0, 6222.0])) == [300, 500, 1000, 2000, 3000, 5000]
    assert _area_ticks(np.array([np.nan])) == []


def test_the_committed_fidelity_campaign_meets_issue_16s_bars(root, shared_data):
    """data/campaigns/fidelity_seed_study's 17 buildings its compute level was fitted on (the
    'fit' part of its parts.yaml, 3 runs each) against the seed study's table: issue #16's five
    bars (docs/fidelity.md)."""
    from slam_predict.collect.fidelity_parts import load_parts, part_comparison

    campaign = root / "data" / "campaigns" / "fidelity_seed_study"
    thesis = read_thesis_table(shared_data / "thesis" / "stats_realistic.csv")
    fit = load_parts(campaign / "parts.yaml")["fit"]
    part = part_comparison(compare_campaign(campaign, thesis, min_coverage=0.5), "fit", fit)
    assert (len(part.rows), part.runs) == (17, 51)
    failed = [bar.label for bar in ACCEPTANCE if not bar.holds(part)]
    assert not failed, failed


def test_the_campaign_bench_refuses_missing_data(root, tmp_path):
    import subprocess

    env = {"PATH": "/usr/bin:/bin", "SLAM_PREDICT_DATA": str(tmp_path / "none")}
    done = subprocess.run(["bash", str(root / "bench" / "bench_fidelity_campaign.sh")],
                          env=env, capture_output=True, text=True)
    assert done.returncode == 2
    assert done.stderr.strip().endswith("not found (set SLAM_PREDICT_DATA)")
    assert len(done.stderr.strip().splitlines()) == 1
