"""``slam-predict report``: the page is written atomically; bad inputs give one line, exit 2."""
from __future__ import annotations

import shutil

import pytest

from slam_predict.cli.main import main

from .conftest import Page


def run(capsys, *argv):
    code = main(["report", *map(str, argv)])
    out, err = capsys.readouterr()
    return code, out, err


def no_temporaries(folder):
    return not [p for p in folder.iterdir() if p.name.startswith(".") and ".tmp" in p.name]


def test_writes_the_page(campaign_dir, tmp_path, capsys):
    out = tmp_path / "site" / "report.html"
    code, stdout, err = run(capsys, campaign_dir, "--out", out, "--title", "Demo")
    assert code == 0, err
    assert str(out) in stdout
    page = Page(out.read_text(encoding="utf-8"))
    assert page.headings[0] == "Demo"
    assert page.table(["world", "runs", "trans_mean [m]"])["rows"]
    assert no_temporaries(out.parent)


def test_real_features_of_a_shipped_world(campaign_dir, model_dir, tmp_path, capsys):
    """World folder 'tiny' → worlds/tiny.world is found and featurised for the prediction."""
    data = tmp_path / "data"
    shutil.copytree(campaign_dir, data)
    (data / "alpha").rename(data / "tiny")
    out = tmp_path / "r.html"
    code, _, err = run(capsys, data, "--out", out, "--models-dir", model_dir)
    assert code == 0, err
    page = Page(out.read_text(encoding="utf-8"))
    worlds = {row[0] for row in page.table(["world", "runs", "component"])["rows"]}
    assert worlds == {"tiny"}                       # beta has no world file: a note
    assert any(n.startswith("beta: no prediction") for n in page.notes)
    assert any("summary.csv is stale" in n for n in page.notes)


@pytest.mark.parametrize("case, message", [
    ("missing", "campaign folder not found"),
    ("empty", "not a slam-predict campaign"),
    ("file", "not a folder"),
    ("models_missing", "models folder not found"),
    ("models_empty", "no model folder (with card.json) found"),
    ("out_is_folder", "--out is a folder"),
    ("out_below_file", "cannot be created"),
])
def test_bad_inputs(campaign_dir, tmp_path, capsys, case, message):
    data, out, extra = campaign_dir, tmp_path / "report.html", []
    named = None
    if case == "missing":
        data = named = tmp_path / "nowhere"
    elif case == "empty":
        data = named = tmp_path / "empty"
        data.mkdir()
    elif case == "file":
        data = named = tmp_path / "summary.csv"
        data.write_text("world\n")
    elif case == "models_missing":
        named = tmp_path / "models"
        extra = ["--models-dir", named]
    elif case == "models_empty":
        named = tmp_path / "models"
        named.mkdir()
        extra = ["--models-dir", named]
    elif case == "out_is_folder":
        out = named = tmp_path / "folder"
        out.mkdir()
    elif case == "out_below_file":
        (tmp_path / "plain").write_text("")
        out = named = tmp_path / "plain" / "report.html"
    code, stdout, err = run(capsys, data, "--out", out, *extra)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("slam-predict report: error: ")
    assert message in lines[0] and str(named) in lines[0]
    assert "Traceback" not in err and stdout == ""
    assert not (tmp_path / "report.html").exists()
    assert no_temporaries(tmp_path)


def test_worlds_dir_is_searched_first(campaign_dir, model_dir, tmp_path, capsys, root):
    """--worlds DIR: beta.world there is found (without it beta has no world file); a
    --worlds that is not a folder is one line, exit 2."""
    data = tmp_path / "data"
    shutil.copytree(campaign_dir, data)
    worlds = tmp_path / "worlds"
    worlds.mkdir()
    for suffix in (".world", ".png"):
        shutil.copy(root / "worlds" / f"tiny{suffix}", worlds / f"tiny{suffix}")
    (worlds / "tiny.world").rename(worlds / "beta.world")
    out = tmp_path / "r.html"
    code, _, err = run(capsys, data, "--out", out, "--models-dir", model_dir,
                       "--worlds", worlds)
    assert code == 0, err
    page = Page(out.read_text(encoding="utf-8"))
    rows = page.table(["world", "runs", "component"])["rows"]
    assert "beta" in {row[0] for row in rows}
    code, _, err = run(capsys, data, "--out", tmp_path / "x.html", "--worlds",
                       tmp_path / "nowhere")
    assert code == 2 and "--worlds: not a folder" in err and len(err.splitlines()) == 1
