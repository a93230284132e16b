"""The scratch folder the docs' commands run in: the repository's worlds/, config/ and models/
(symlinked) and the robot file that docs/tutorial.md saves."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
TUTORIAL = (ROOT / "docs" / "tutorial.md").read_text(encoding="utf-8")
ROBOT_FILE = re.compile(r"Save this as `([\w.]+)`:\n\n```yaml\n(.*?)```", re.S)


@pytest.fixture
def scratch(tmp_path, monkeypatch):
    """A folder like the repository's top, plus the tutorial's robot file, as the cwd."""
    for name in ("worlds", "config", "models"):
        (tmp_path / name).symlink_to(ROOT / name, target_is_directory=True)
    name, body = ROBOT_FILE.search(TUTORIAL).groups()
    (tmp_path / name).write_text(body, encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    return tmp_path
