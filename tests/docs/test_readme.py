"""The README's quick start shows real output: every `$ slam-predict ...` line of its console
blocks that is followed by output is run, and prints exactly that output."""
from __future__ import annotations

import contextlib
import io
import re
import shlex
from pathlib import Path

import pytest

from slam_predict.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
BLOCK = re.compile(r"```console\n(.*?)```", re.S)


def shown_commands(text: str) -> list[tuple[str, list[str]]]:
    """(command, its output lines) for every `$ slam-predict` line with output below it."""
    found = []
    for block in BLOCK.findall(text):
        lines = block.rstrip("\n").split("\n")
        for i, line in enumerate(lines):
            if not line.startswith("$ slam-predict "):
                continue
            output = []
            for nxt in lines[i + 1:]:
                if nxt.startswith("$ "):
                    break
                output.append(nxt)
            if output:
                found.append((line[2:], output))
    return found


COMMANDS = shown_commands((ROOT / "README.md").read_text(encoding="utf-8"))


def test_the_quick_start_shows_output():
    assert COMMANDS, "no `$ slam-predict` command with output in the README"


@pytest.mark.parametrize("command, output", COMMANDS, ids=[c for c, _ in COMMANDS])
def test_the_readme_output_is_what_the_command_prints(command, output, monkeypatch):
    monkeypatch.chdir(ROOT)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(shlex.split(command)[1:]) == 0
    assert out.getvalue().rstrip("\n").split("\n") == output
