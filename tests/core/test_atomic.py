"""Atomic writes leave either the old or the new content, never a partial file."""
import pytest

from slam_predict.atomic import atomic_dir, atomic_path, write_text


def test_write_text_replaces(tmp_path):
    target = tmp_path / "a" / "f.txt"
    write_text(target, "one")
    write_text(target, "two")
    assert target.read_text() == "two"
    assert [p.name for p in target.parent.iterdir()] == ["f.txt"]


def test_failed_write_keeps_old_content(tmp_path):
    target = tmp_path / "f.txt"
    write_text(target, "old")
    with pytest.raises(RuntimeError):
        with atomic_path(target) as tmp:
            tmp.write_text("half")
            raise RuntimeError("boom")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["f.txt"]


def test_atomic_dir(tmp_path):
    final = tmp_path / "run1"
    with atomic_dir(final) as tmp:
        (tmp / "run.json").write_text("{}")
    assert (final / "run.json").exists()
    with pytest.raises(ValueError):
        with atomic_dir(final) as tmp:
            (tmp / "other").write_text("x")
            raise ValueError
    assert sorted(p.name for p in final.iterdir()) == ["run.json"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run1"]


def test_files_get_umask_permissions(tmp_path):
    import os
    import stat
    mask = os.umask(0o022)
    try:
        write_text(tmp_path / "f.txt", "x")
        with atomic_dir(tmp_path / "d") as tmp:
            (tmp / "a").write_text("y")
    finally:
        os.umask(mask)
    assert stat.S_IMODE((tmp_path / "f.txt").stat().st_mode) == 0o644
    assert stat.S_IMODE((tmp_path / "d").stat().st_mode) == 0o755
