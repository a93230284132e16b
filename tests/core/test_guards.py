"""cli.guards: output folder/file checks and numeric options, before any work."""
from __future__ import annotations

import pytest

from slam_predict.cli.guards import (
    check_at_least,
    check_creatable,
    check_out_dir,
    check_out_file,
    check_positive,
    plural,
)
from slam_predict.errors import InputError


def test_out_dir_new_empty_and_forced(tmp_path):
    check_out_dir(tmp_path / "new" / "deeper", force=False)
    (tmp_path / "empty").mkdir()
    check_out_dir(tmp_path / "empty", force=False)
    (tmp_path / "full").mkdir()
    (tmp_path / "full" / "thesis.tex").write_text("x")
    with pytest.raises(InputError) as info:
        check_out_dir(tmp_path / "full", force=False)
    assert info.value.one_line() == (f"{tmp_path / 'full'}: --out folder exists and is not "
                                     "empty; use --force to replace it or choose another folder")
    check_out_dir(tmp_path / "full", force=True)
    assert (tmp_path / "full" / "thesis.tex").read_text() == "x"   # a check never writes


def test_out_dir_that_is_a_file_is_refused_even_forced(tmp_path):
    (tmp_path / "f").write_text("x")
    with pytest.raises(InputError, match="must be a folder; this exists and is not a folder"):
        check_out_dir(tmp_path / "f", force=True)


def test_out_file(tmp_path):
    check_out_file(tmp_path / "a" / "b.json", force=False)
    (tmp_path / "b.json").write_text("{}")
    with pytest.raises(InputError, match=r"b\.json: --out file exists; use --force"):
        check_out_file(tmp_path / "b.json", force=False)
    check_out_file(tmp_path / "b.json", force=True)
    with pytest.raises(InputError, match="--out is a folder; give the file to write"):
        check_out_file(tmp_path, force=True)


def test_path_under_a_file_can_never_be_created(tmp_path):
    (tmp_path / "f").write_text("x")
    with pytest.raises(InputError) as info:
        check_out_dir(tmp_path / "f" / "sub" / "out", force=True)
    assert info.value.problem == (f"--out cannot be created: {tmp_path / 'f'} "
                                  "is a file, not a folder")
    with pytest.raises(InputError, match="--relations cannot be created"):
        check_out_file(tmp_path / "f" / "r.txt", force=True, option="--relations")


def test_read_only_parent(read_only_folder):
    with pytest.raises(InputError, match="no permission to write in"):
        check_creatable(read_only_folder / "x" / "y")


def test_numbers():
    check_at_least(1, 1, "--jobs")
    check_at_least(None, 1, "--jobs")
    with pytest.raises(InputError, match="--jobs must be ≥ 1, got 0"):
        check_at_least(0, 1, "--jobs")
    check_positive(1e-9, "--max-time")
    for bad in (0.0, -1.0, float("nan")):
        with pytest.raises(InputError, match="--max-time must be > 0"):
            check_positive(bad, "--max-time")


def test_plural():
    assert [plural(n, "run") for n in (0, 1, 2)] == ["0 runs", "1 run", "2 runs"]
    assert plural(1, "analysis", "analyses") == "1 analysis"
    assert plural(3, "analysis", "analyses") == "3 analyses"


def test_force_never_replaces_a_folder_holding_an_input_or_the_current_folder(tmp_path,
                                                                               monkeypatch):
    folder = tmp_path / "run"
    (folder / "sub").mkdir(parents=True)
    (folder / "sub" / "in.log").write_text("x")
    with pytest.raises(InputError, match=r"--out holds the input .*in\.log; --force would "
                                         r"delete it"):
        check_out_dir(folder, force=True, inputs=(None, folder / "sub" / "in.log"))
    check_out_dir(folder, force=True, inputs=(tmp_path / "runner.log",))  # a sibling: fine
    monkeypatch.chdir(folder / "sub")
    with pytest.raises(InputError, match="--out holds the current folder"):
        check_out_dir(folder, force=True)
    with pytest.raises(InputError, match="--out holds the current folder"):
        check_out_dir(".", force=True)


def test_the_current_folder_is_never_an_output_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)   # empty: replacing it would still rename the current folder
    with pytest.raises(InputError, match="--out holds the current folder"):
        check_out_dir(".", force=False)
