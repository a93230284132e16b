"""learn.provenance: a summary's campaign folder and the card sources it gives."""
import json

from slam_predict.learn.provenance import campaign_folder, campaign_sources


def test_campaign_folder_needs_runs_or_a_campaign_json(tmp_path):
    table = tmp_path / "camp" / "summary.csv"
    table.parent.mkdir()
    table.write_text("world\n")
    assert campaign_folder(table) is None                 # a bare table (e.g. the seed study's)
    run = tmp_path / "camp" / "w" / "run_000"
    run.mkdir(parents=True)
    (run / "run.json").write_text("{}")
    assert campaign_folder(table) == table.parent.resolve()


def test_sources_name_the_settings_only_when_every_campaign_agrees(tmp_path):
    folders = []
    for name, settings in (("a", "config/x.yaml"), ("b", "config/x.yaml"), ("c", "config/y.yaml")):
        folder = tmp_path / name
        folder.mkdir()
        (folder / "campaign.json").write_text(json.dumps({"settings_file": settings}))
        folders.append(folder)
    same = campaign_sources(folders[:2])
    assert same["settings"] == "config/x.yaml" and len(same["data"]) == 2
    mixed = campaign_sources(folders)["settings"]      # different files: one per campaign
    assert list(mixed.values()) == ["config/x.yaml", "config/x.yaml", "config/y.yaml"]
    assert list(mixed) == campaign_sources(folders)["data"]
    assert "settings" not in campaign_sources([tmp_path])   # no campaign.json
    assert "settings" not in campaign_sources([*folders, tmp_path])


def test_sources_carry_the_settings_files_fitted_settings(tmp_path):
    """The fidelity chain's fitted map-rebuild cost reaches the card; a chain without one adds
    nothing."""
    for name, settings in (("gm", "config/fidelity/seed_study.yaml"),
                           ("karto", "config/fidelity/seed_study_karto.yaml")):
        (tmp_path / name).mkdir()
        (tmp_path / name / "campaign.json").write_text(json.dumps({"settings_file": settings}))
    fitted = campaign_sources([tmp_path / "gm"])["fitted"]
    assert list(fitted) == ["slam_compute.rebuild_s_per_line_cell"]
    assert "fitted on the 17 'fit' buildings" in fitted["slam_compute.rebuild_s_per_line_cell"]
    assert "fitted" not in campaign_sources([tmp_path / "karto"])   # set to null there


def test_campaigns_of_two_settings_files_join_their_fitted_settings(tmp_path):
    """The fidelity campaign and a robot campaign (two files, one fitted rebuild cost)."""
    for name, settings in (("fid", "config/fidelity/seed_study.yaml"),
                           ("rob", "config/robot_campaign/settings.yaml")):
        (tmp_path / name).mkdir()
        (tmp_path / name / "campaign.json").write_text(json.dumps({"settings_file": settings}))
    sources = campaign_sources([tmp_path / "fid", tmp_path / "rob"])
    assert sorted(sources["settings"].values()) == ["config/fidelity/seed_study.yaml",
                                                    "config/robot_campaign/settings.yaml"]
    assert list(sources["fitted"]) == ["slam_compute.rebuild_s_per_line_cell"]


def test_an_unreadable_campaign_json_is_a_one_line_error(tmp_path):
    import pytest

    from slam_predict.errors import InputError

    (tmp_path / "campaign.json").write_text("{not json")
    with pytest.raises(InputError, match="unreadable campaign record"):
        campaign_sources([tmp_path])
