"""docs/tutorial.md shows real output: its `$ slam-predict ...` commands are run in a scratch
folder holding the repository's worlds/, config/ and models/ and the tutorial's robot file, and
print exactly the lines the tutorial shows. The `--simulate` step takes about a minute of CPU."""
from __future__ import annotations

import contextlib
import io
import shlex

import pytest

from slam_predict.cli.main import main

from .conftest import ROBOT_FILE, TUTORIAL
from .test_readme import shown_commands

COMMANDS = shown_commands(TUTORIAL)


def command_params(commands: list[tuple[str, list[str]]]) -> list:
    """One pytest param per (command, output); the --simulate ones are slow."""
    return [pytest.param(command, output, id=command,
                         marks=[pytest.mark.slow] if "--simulate" in command else [])
            for command, output in commands]


def test_the_tutorial_shows_every_step():
    commands = [c for c, _ in COMMANDS]
    assert any("--robot" in c and c.endswith(".yaml") for c in commands), "no robot file step"
    assert any("--robot" in c and not c.endswith(".yaml") for c in commands), "no robot name"
    assert any("--simulate" in c for c in commands), "no --simulate step"
    assert ROBOT_FILE.search(TUTORIAL), "the robot file the tutorial saves is missing"


def assert_prints(command: str, output: list[str]) -> None:
    """``command`` (a `slam-predict ...` line) exits 0 and prints exactly ``output``."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(shlex.split(command)[1:]) == 0
    assert out.getvalue().rstrip("\n").split("\n") == output


@pytest.mark.parametrize("command, output", command_params(COMMANDS))
def test_the_tutorial_output_is_what_the_command_prints(command, output, scratch):
    assert_prints(command, output)
