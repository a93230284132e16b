"""Paths written into run records: relative to the project inside it, absolute outside."""
from pathlib import Path

from slam_predict.paths import PROJECT_ROOT, portable_path


def test_project_files_are_recorded_relative_to_the_project_root():
    assert (PROJECT_ROOT / "config" / "collect.yaml").is_file()
    assert portable_path(PROJECT_ROOT / "config" / "collect.yaml") == "config/collect.yaml"
    assert portable_path(str(PROJECT_ROOT / "worlds" / ".." / "worlds" / "tiny.world")) == \
        "worlds/tiny.world"


def test_files_outside_the_project_stay_absolute(tmp_path):
    outside = tmp_path / "my.world"
    assert portable_path(outside) == str(outside.resolve())
    assert Path(portable_path(outside)).is_absolute()


def test_relative_input_is_resolved_from_the_current_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(PROJECT_ROOT)
    assert portable_path("config/collect.yaml") == "config/collect.yaml"
    monkeypatch.chdir(tmp_path)
    assert portable_path("x.yaml") == str((tmp_path / "x.yaml").resolve())


def test_empty_path_stays_empty():
    assert portable_path("") == ""
