"""docs/tutorial.md shows real output: its `$ slam-predict ...` commands are run in a scratch
folder holding the repository's worlds/, config/ and models/ and the tutorial's robot file, and
print exactly the lines the tutorial shows. The `--simulate` step takes about a minute of CPU."""
from __future__ import annotations

import contextlib
import io
import re
import shlex
from pathlib import Path

import pytest

from slam_predict.cli.main import main

from .test_readme import shown_commands

ROOT = Path(__file__).resolve().parents[2]
TEXT = (ROOT / "docs" / "tutorial.md").read_text(encoding="utf-8")
COMMANDS = shown_commands(TEXT)
ROBOT_FILE = re.compile(r"Save this as `([\w.]+)`:\n\n```yaml\n(.*?)```", re.S)


def params():
    """One pytest param per command; the --simulate ones are slow."""
    return [pytest.param(command, output, id=command,
                         marks=[pytest.mark.slow] if "--simulate" in command else [])
            for command, output in COMMANDS]


def test_the_tutorial_shows_every_step():
    commands = [c for c, _ in COMMANDS]
    assert any("--robot" in c and c.endswith(".yaml") for c in commands), "no robot file step"
    assert any("--robot" in c and not c.endswith(".yaml") for c in commands), "no robot name"
    assert any("--simulate" in c for c in commands), "no --simulate step"
    assert ROBOT_FILE.search(TEXT), "the robot file the tutorial saves is missing"


@pytest.fixture
def scratch(tmp_path, monkeypatch):
    """A folder like the repository's top, plus the tutorial's robot file."""
    for name in ("worlds", "config", "models"):
        (tmp_path / name).symlink_to(ROOT / name, target_is_directory=True)
    name, body = ROBOT_FILE.search(TEXT).groups()
    (tmp_path / name).write_text(body, encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.mark.parametrize("command, output", params())
def test_the_tutorial_output_is_what_the_command_prints(command, output, scratch):
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(shlex.split(command)[1:]) == 0
    assert out.getvalue().rstrip("\n").split("\n") == output
