"""collect.simulate: the measured components of run records, the --max-runs note, the plan's
identity and the refusal of another plan's campaign."""
import json

import numpy as np
import pytest

from slam_predict.collect import campaign
from slam_predict.collect.simulate import (
    cap_note,
    check_resume,
    measured,
    plan_identity,
    write_plan_world,
)
from slam_predict.world.load import load_plan


def records(trans, rot):
    return [{"metric": {"trans_mean": t, "rot_mean": r}} for t, r in zip(trans, rot, strict=True)]


def test_measured_components_by_hand():
    """ε_t 0.1, 0.2, 0.3, 0.4 and ε_r 0.01, 0.01, 0.02, 0.02 (t_{0.975,3} = 3.182)."""
    got = measured(records([0.1, 0.2, 0.3, 0.4], [0.01, 0.01, 0.02, 0.02]))
    assert got["trans_mean"]["value"] == pytest.approx(0.25)
    half = 3.182 * np.sqrt(0.05 / 3) / 2
    assert got["trans_mean"]["low"] == pytest.approx(0.25 - half, abs=1e-4)
    assert got["trans_mean"]["high"] == pytest.approx(0.25 + half, abs=1e-4)
    assert got["trans_std"]["value"] == pytest.approx(np.sqrt(0.0125))
    assert got["rot_mean"]["value"] == pytest.approx(0.015)
    assert got["rot_std"]["value"] == pytest.approx(0.005)
    assert got["rot_mean"]["unit"] == "rad" and got["trans_std"]["unit"] == "m"
    assert {e["runs"] for e in got.values()} == {4}


def test_mean_interval_is_clipped_at_zero_and_one_run_has_none():
    got = measured(records([0.01, 0.2], [0.001, 0.05]))
    assert got["trans_mean"]["low"] == 0.0 and got["rot_mean"]["low"] == 0.0
    one = measured(records([0.1], [0.01]))
    assert one["trans_mean"]["low"] is None and one["trans_std"]["high"] is None
    assert one["trans_std"]["status"] == one["rot_std"]["status"] == "n/a"
    assert one["trans_std"]["value"] is None and one["trans_mean"]["value"] == 0.1
    with pytest.raises(ValueError):
        measured([])


def test_cap_note_only_when_the_rule_asks_for_more_than_the_cap():
    rng = np.random.default_rng(0)
    wide = records(rng.normal(0.3, 0.2, 10), rng.normal(0.02, 0.001, 10))
    note = cap_note(wide, 10)
    assert note and "--max-runs 10" in note
    assert cap_note(wide, 60) is None  # not at the cap: the batch goes on by itself
    narrow = records(rng.normal(0.3, 0.01, 10), rng.normal(0.02, 0.001, 10))
    assert cap_note(narrow, 10) is None


def test_plan_identity_and_refusal_of_another_plan(root, tmp_path):
    tiny = load_plan(root / "worlds" / "tiny.world")
    moved = load_plan(root / "worlds" / "tiny.world", start=[-3.5, -2.5])
    assert plan_identity(tiny) == plan_identity(load_plan(root / "worlds" / "tiny.world"))
    assert plan_identity(moved)["world_sha256"] != plan_identity(tiny)["world_sha256"]
    assert plan_identity(moved)["bitmap_sha256"] == plan_identity(tiny)["bitmap_sha256"]
    path = write_plan_world(tiny, tmp_path)
    assert load_plan(path).occupied.tolist() == tiny.occupied.tolist()
    record = {"base_seed": 0, "settings": {}, "plan": plan_identity(tiny)}
    (tmp_path / campaign.CAMPAIGN_JSON).write_text(json.dumps(record))
    check_resume(tmp_path, record)
    with pytest.raises(campaign.CampaignMismatch, match="another version of plan 'tiny'"):
        check_resume(tmp_path, {**record, "plan": plan_identity(moved)})
    collect_record = {k: v for k, v in record.items() if k != "plan"}
    (tmp_path / campaign.CAMPAIGN_JSON).write_text(json.dumps(collect_record))
    with pytest.raises(campaign.CampaignMismatch, match="'slam-predict collect' campaign"):
        check_resume(tmp_path, record)
    assert campaign.mismatch(collect_record, collect_record) is None  # collect: unchanged


@pytest.fixture
def fake_runs(monkeypatch):
    """`predict --simulate` with the batch's stand-in episode (tests/collect/fake_episode.py:
    ε_t uniform in [0.1, 0.3] m, so the run-count rule asks for about 15 runs)."""
    import functools

    from slam_predict.collect import batch

    monkeypatch.setattr(batch, "BatchConfig",
                        functools.partial(batch.BatchConfig, episode="fake_episode:run_episode"))


def simulate_auto(root, out, max_runs, capsys):
    from slam_predict.cli.main import main

    code = main(["predict", str(root / "worlds" / "tiny.world"), "--simulate", "auto", "--out",
                 str(out), "--max-runs", str(max_runs), "--no-progress", "--json",
                 "--component", "trans_mean"])
    assert code == 0, capsys.readouterr().err
    return json.loads(capsys.readouterr().out)["simulation"]


def test_auto_follows_the_run_count_rule_and_says_when_capped(root, tmp_path, fake_runs,
                                                              capsys):
    from slam_predict.collect.store import RunStore
    from slam_predict.metric.sampling import run_count

    sim = simulate_auto(root, tmp_path / "capped", 12, capsys)
    assert sim["runs"] == 12 and sim["runs_new"] == 12
    assert len(sim["notes"]) == 1 and "--max-runs 12" in sim["notes"][0]
    sim = simulate_auto(root, tmp_path / "free", 60, capsys)
    runs = RunStore(tmp_path / "free").records("tiny")
    assert sim["runs"] == len(runs) > 12 and sim["notes"] == []
    values = [[r["metric"][k] for r in runs] for k in ("trans_mean", "rot_mean")]
    assert not run_count(*values).more_needed  # stopped once the rule was met, before the cap
    assert run_count(*[v[:10] for v in values]).more_needed  # the pilot alone was not enough
