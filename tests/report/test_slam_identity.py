"""The SLAM identity of a run record: ``slam.params_hash``, or ``config_hashes.gmapping`` in
records written before the ``slam`` entry; the model-card check reads both."""
from pathlib import Path

from slam_predict.report.campaign import Campaign, Run, WorldRuns
from slam_predict.report.models import ModelEntry
from slam_predict.report.predictions import setup_notes, slam_config_hash

OLD = {"config_hashes": {"gmapping": "aaaaaaaaaaaa"}}
NEW = {"config_hashes": {"dummy": "bbbbbbbbbbbb"},
       "slam": {"type": "dummy", "params_hash": "bbbbbbbbbbbb"}}


def campaign(*records):
    runs = [Run("w", f"run_{i:03d}", Path("/nonexistent"), r) for i, r in enumerate(records)]
    return Campaign(Path("/nonexistent"), {"w": WorldRuns("w", runs)}, {})


def test_both_record_forms_name_their_slam_configuration():
    old, new = campaign(OLD, NEW).runs
    assert slam_config_hash(old) == "aaaaaaaaaaaa" and slam_config_hash(new) == "bbbbbbbbbbbb"
    assert slam_config_hash(Run("w", "r", Path("/x"), {})) is None


def test_card_check_accepts_old_and_new_records():
    entry = ModelEntry(Path("/m"), card={"slam_config_hash": "aaaaaaaaaaaa"})
    assert setup_notes(entry, campaign(OLD)) == []
    assert setup_notes(entry, campaign(OLD, NEW)) == []   # the card's configuration ran too
    other = ModelEntry(Path("/m"), card={"slam_config_hash": "cccccccccccc"})
    notes = setup_notes(other, campaign(OLD, NEW))
    assert len(notes) == 1 and "aaaaaaaaaaaa" in notes[0] and "bbbbbbbbbbbb" in notes[0]
    entry = ModelEntry(Path("/m"), card={"slam_config_hash": "bbbbbbbbbbbb"})
    assert setup_notes(entry, campaign(NEW)) == []
