"""Fidelity by declared parts: part comparisons, the widest ratio, run ends, the parts file."""
import json

import numpy as np
import pytest
from test_fidelity import tables  # noqa: F401  (fixture)

from slam_predict.cli.main import main
from slam_predict.collect.fidelity import compare_campaign, read_thesis_table
from slam_predict.collect.fidelity_parts import (
    CHAIN_BARS,
    FULL_COVERAGE,
    load_parts,
    part_comparison,
    run_ends,
)
from slam_predict.errors import InputError


def test_a_part_is_its_buildings_only(tables):  # noqa: F811
    camp, thesis, theirs, ours = tables
    whole = compare_campaign(camp, read_thesis_table(thesis))
    part = part_comparison(whole, "fit", ["a", "d", "not_there"])
    assert [r["world"] for r in part.rows] == ["a", "d"] and set(part.per_run) == {"a", "d"}
    mine = np.array([np.mean(ours["a"]), np.mean(ours["d"])])
    assert part.median_ratio("trans_mean") == pytest.approx(
        np.median(mine / np.array([theirs["a"], theirs["d"]])))


def test_widest_ratio_against_a_plain_search(tables):  # noqa: F811
    camp, thesis, theirs, ours = tables
    c = compare_campaign(camp, read_thesis_table(thesis))
    ratios = {w: np.mean(ours[w]) / theirs[w] for w in "abcd"}
    widest = max(ratios.values(), key=lambda r: max(r, 1 / r))
    assert c.extreme_ratio("trans_mean") == pytest.approx(widest)   # b: 0.4 / 0.2 = 2.0
    bar = next(b for b in CHAIN_BARS if b.figure == "extreme:trans_mean")
    assert not bar.holds(c)
    assert bar.holds(part_comparison(c, "ok", ["a", "c"]))


def test_run_ends_lists_stuck_and_incomplete_runs(tmp_path):
    """Stuck at the end: a run stopped 'stuck' (before 2026-12-05), a record without
    ``stuck_at_end`` that says ``stuck``, or one whose ``stuck_at_end`` says so; a robot stuck
    for a while that got out is listed apart."""
    for world, index, reason, cov, stuck in [
            ("a", 0, "map_converged", 0.99, False), ("a", 1, "stuck", 0.99, None),
            ("a", 2, "map_converged", 0.99, True),
            ("a", 3, "map_converged", 0.99, (True, True)),
            ("a", 4, "map_converged", 0.99, (True, False)),
            ("b", 0, "map_converged", FULL_COVERAGE - 0.01, False), ("c", 0, "stuck", 0.5, None)]:
        folder = tmp_path / world / f"run_{index:03d}"
        folder.mkdir(parents=True)
        record = {"run_index": index, "stop_reason": reason, "coverage": cov}
        if world == "b":
            record["coverage_swept"] = 0.992
        if isinstance(stuck, tuple):
            record["stuck"] = {"longest_still_s": 400.0, "stuck": stuck[0],
                               "stuck_at_end": stuck[1], "radius_m": 1.0}
        elif stuck is not None:
            record["stuck"] = {"longest_still_s": 400.0 if stuck else 3.0, "stuck": stuck}
        (folder / "run.json").write_text(json.dumps(record))
    ends = run_ends([tmp_path], ["a", "b"])
    assert ends["stuck"] == ["a run 1 (stuck, coverage 0.990)",
                             "a run 2 (map_converged, coverage 0.990)",
                             "a run 3 (map_converged, coverage 0.990)"]
    assert ends["stuck for a while, got out"] == ["a run 4 (map_converged, coverage 0.990)"]
    assert ends["low coverage"] == ["b run 0 (map_converged, coverage 0.940, floor swept 0.992)"]


@pytest.mark.parametrize("text, problem", [
    ("fit: [a]\n", "needs a 'parts' mapping"),
    ("parts: {fit: a}\n", "part 'fit' must be a list"),
    ("parts: {fit: [a], judge: [b, a]}\n", "building 'a' is in parts 'fit' and 'judge'"),
])
def test_bad_parts_files_name_the_problem(tmp_path, text, problem):
    path = tmp_path / "parts.yaml"
    path.write_text(text)
    with pytest.raises(InputError, match=problem):
        load_parts(path)


def test_cli_reports_each_part(tables, tmp_path, capsys):  # noqa: F811
    camp, thesis, _, _ = tables
    parts = tmp_path / "parts.yaml"
    parts.write_text("parts:\n  fit: [a, b]\n  judge: [c, d, e]\n")
    assert main(["fidelity", str(camp), "--thesis", str(thesis), "--parts", str(parts)]) == 0
    out = capsys.readouterr().out
    assert "#### Part 'fit': 2 of 2 buildings, 4 runs" in out
    assert "#### Part 'judge': 2 of 3 buildings, 4 runs" in out
    assert "- not collected yet (or no run kept): e" in out
    assert out.count("ε_t median ratio in [0.9, 1.1]") == 2
    parts.write_text("parts: {fit: [a], judge: [a]}\n")
    assert main(["fidelity", str(camp), "--thesis", str(thesis), "--parts", str(parts)]) == 2
    assert "parts.yaml" in capsys.readouterr().err
