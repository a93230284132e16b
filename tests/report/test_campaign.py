"""Reading a campaign for the report: rows equal summary.csv, damaged pieces become notes."""
from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.report.campaign import load_campaign

from .fake_campaign import ERRORS, copy


def test_worlds_runs_and_rows_match_summary_csv(campaign_dir):
    campaign = load_campaign(campaign_dir)
    assert list(campaign.worlds) == ["alpha", "beta"]
    assert [len(w.runs) for w in campaign.worlds.values()] == [3, 2]
    assert campaign.notes == []                      # summary.csv present and up to date
    with open(campaign_dir / "summary.csv") as handle:
        csv_rows = {r["world"]: r for r in csv.DictReader(handle)}
    for row in campaign.summary_rows():
        trans = np.array([t for t, _ in ERRORS[row["world"]]])
        rot = np.array([r for _, r in ERRORS[row["world"]]])
        assert row["trans_mean"] == pytest.approx(trans.mean())
        assert row["trans_std"] == pytest.approx(trans.std())   # ddof 0, as the thesis
        assert row["rot_mean"] == pytest.approx(rot.mean())
        assert row["rot_std"] == pytest.approx(rot.std())
        for column in ("trans_mean", "trans_std", "rot_mean", "rot_std", "coverage_mean"):
            assert row[column] == pytest.approx(float(csv_rows[row["world"]][column]), rel=1e-8)
    beta = campaign.worlds["beta"]
    assert [r.has_map for r in beta.runs] == [True, False]
    assert [r.has_trajectories for r in beta.runs] == [True, False]


def test_stale_and_missing_summary_csv_are_notes(campaign_dir, tmp_path):
    data = copy(campaign_dir, tmp_path / "stale")
    record_path = data / "alpha" / "run_002" / "run.json"
    record = json.loads(record_path.read_text())
    record["metric"]["trans_mean"] = 0.9
    record_path.write_text(json.dumps(record))
    campaign = load_campaign(data)
    assert any("summary.csv is stale for alpha" in n for n in campaign.notes)
    assert campaign.worlds["alpha"].row["trans_mean"] == pytest.approx((0.1 + 0.2 + 0.9) / 3)
    (data / "summary.csv").unlink()
    assert any("summary.csv is missing" in n for n in load_campaign(data).notes)


def test_broken_runs_are_left_out_with_a_note(campaign_dir, tmp_path):
    data = copy(campaign_dir, tmp_path / "broken")
    (data / "alpha" / "run_001" / "run.json").write_text("{not json")
    record_path = data / "beta" / "run_000" / "run.json"
    record = json.loads(record_path.read_text())
    del record["metric"]["rot_mean"]
    record["coverage"] = None                     # allowed: the ROS path may not know it
    record_path.write_text(json.dumps(record))
    (data / "alpha" / ".run_003.abc.tmp").mkdir()
    (data / "alpha" / "run_004").mkdir()          # no run.json: an incomplete run
    campaign = load_campaign(data)
    alpha, beta = campaign.worlds["alpha"], campaign.worlds["beta"]
    assert [r.run_id for r in alpha.runs] == ["run_000", "run_002"]
    assert any("run_001: run.json unreadable" in n for n in alpha.notes)
    assert any("interrupted run" in n for n in alpha.notes)
    assert any("run_004: no run.json" in n for n in alpha.notes)
    assert alpha.row["trans_mean"] == pytest.approx(0.2)
    assert any("run_000: run.json lacks metric.rot_mean" in n for n in beta.notes)
    assert beta.row["runs"] == 1 and beta.row["trans_mean"] == pytest.approx(0.07)
    assert any("stale" in n for n in campaign.notes)


def test_summary_csv_alone_is_a_campaign(campaign_dir, tmp_path):
    data = tmp_path / "csv_only"
    data.mkdir()
    (data / "summary.csv").write_text((campaign_dir / "summary.csv").read_text())
    campaign = load_campaign(data)
    assert [r["world"] for r in campaign.summary_rows()] == ["alpha", "beta"]
    assert campaign.summary_rows()[0]["trans_mean"] == pytest.approx(0.2)
    assert any("no usable run record" in n for n in campaign.notes)


@pytest.mark.parametrize("case, message", [
    ("missing", "campaign folder not found"),
    ("file", "not a folder"),
    ("empty", "not a slam-predict campaign"),
    ("other", "not a slam-predict campaign"),
])
def test_not_a_campaign(tmp_path, case, message):
    path = tmp_path / case
    if case == "file":
        path.write_text("x")
    elif case == "empty":
        path.mkdir()
    elif case == "other":
        (path / "stuff" / "run_000").mkdir(parents=True)
        (path / "notes.txt").write_text("hello")
    with pytest.raises(InputError, match=message) as info:
        load_campaign(path)
    assert info.value.path == str(path)
