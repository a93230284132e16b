"""The report page of the fake campaign: self-contained HTML with the right numbers."""
from __future__ import annotations

import base64
import math

import numpy as np
import pytest

from slam_predict.report.build import build_report

from .fake_campaign import ERRORS, HASHES, copy

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def page(campaign_dir):
    from .conftest import Page

    return Page(build_report(campaign_dir, title="Fake <campaign>"))


def test_page_is_self_contained(page):
    assert "script" not in page.tags and "link" not in page.tags and "iframe" not in page.tags
    assert page.headings[0] == "Fake <campaign>"           # escaped, then parsed back
    assert len(page.images) == 2                           # one map per world
    for img in page.images:
        prefix = "data:image/png;base64,"
        assert img["src"].startswith(prefix)
        assert base64.b64decode(img["src"][len(prefix):]).startswith(PNG_MAGIC)


def test_summary_table_numbers(page):
    table = page.table(["world", "runs", "trans_mean [m]"])
    assert table["id"] == "summary"
    rows = page.rows_by_first(table)
    assert set(rows) == set(ERRORS)
    for world, errors in ERRORS.items():
        trans = np.array([t for t, _ in errors])
        rot = np.array([r for _, r in errors])
        row = rows[world]
        assert row["runs"] == str(len(errors))
        assert row["trans_mean [m]"] == f"{trans.mean():.4f}"
        assert row["std of trans_mean over runs [m]"] == f"{trans.std():.4f}"
        assert row["rot_mean [rad]"] == f"{rot.mean():.5f}"
        assert row["rot_mean [deg]"] == f"{math.degrees(rot.mean()):.3f}"
        assert row["std of rot_mean over runs [rad]"] == f"{rot.std():.5f}"
        assert row["std of rot_mean over runs [deg]"] == f"{math.degrees(rot.std()):.3f}"
        assert row["path length [m]"] == f"{40 + np.arange(len(errors)).mean():.1f}"
        assert row["coverage"] == f"{0.9 + 0.01 * np.arange(len(errors)).mean():.3f}"


def test_per_run_tables(page):
    for world, errors in ERRORS.items():
        rows = page.rows_by_first(page.table(["run", "seed"], section=f"World {world}"))
        assert list(rows) == [f"run_{i:03d}" for i in range(len(errors))]
        for i, (trans, rot) in enumerate(errors):
            row = rows[f"run_{i:03d}"]
            assert row["seed"] == str(1000 + i)
            assert row["trans_mean [m]"] == f"{trans:.4f}"
            assert row["rot_mean [deg]"] == f"{math.degrees(rot):.3f}"
            assert row["stop reason"] == ("map_converged" if i else "max_sim_time")
            assert row["relations"] == str(100 + i)
    beta = page.rows_by_first(page.table(["run", "seed"], section="World beta"))
    assert (beta["run_000"]["map"], beta["run_001"]["map"]) == ("yes", "no")
    assert "without map or trajectories: run_001" in page.notes


def test_map_of_the_median_run(page):
    alts = [img["alt"] for img in page.images]
    assert alts == ["SLAM map of alpha run_001", "SLAM map of beta run_000"]


def test_overview(page):
    hashes = page.table(["sim", "gmapping"])
    assert hashes["rows"] == [[*HASHES.values(), "5", "alpha, beta"]]
    stops = page.rows_by_first(page.table(["world", "map_converged", "max_sim_time"]))
    assert stops["alpha"]["map_converged"] == "2" and stops["alpha"]["max_sim_time"] == "1"
    assert page.notes == ["without map or trajectories: run_001"]   # nothing else missing


def test_missing_maps_are_reported_not_fatal(campaign_dir, tmp_path, parse):
    data = copy(campaign_dir, tmp_path / "no_maps")
    for path in list(data.glob("*/run_*/map.*")):
        path.unlink()
    (data / "summary.csv").unlink()
    page = parse(build_report(data))
    assert page.images == []
    assert sum("no map figure" in n for n in page.notes) == 2
    assert any("summary.csv is missing" in n for n in page.notes)
    assert page.rows_by_first(page.table(["world", "runs"]))["alpha"]["trans_mean [m]"] == \
        "0.2000"


def test_unreadable_map_falls_back_to_another_run(campaign_dir, tmp_path, parse):
    data = copy(campaign_dir, tmp_path / "bad_map")
    (data / "alpha" / "run_001" / "map.pgm").write_bytes(b"P5\n3 3\n255\n")   # truncated
    page = parse(build_report(data))
    assert [img["alt"] for img in page.images][0] in ("SLAM map of alpha run_000",
                                                      "SLAM map of alpha run_002")
    assert any(n.startswith("run_001: map or trajectories unreadable") for n in page.notes)
