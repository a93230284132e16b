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
    assert "settings" not in campaign_sources(folders)
    assert "settings" not in campaign_sources([tmp_path])   # no campaign.json
