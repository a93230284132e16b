"""docs/usage.md's command table has a row for every subcommand of `slam-predict`, and its
`$ slam-predict` examples print what it shows (run as tests/docs/test_tutorial.py runs them)."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from slam_predict.cli.main import build_parser
from slam_predict.cli.reference import parsers

from .test_readme import shown_commands
from .test_tutorial import assert_prints, command_params

ROOT = Path(__file__).resolve().parents[2]


def leaf_commands() -> list[str]:
    """Every runnable subcommand ("learn train", "predict"...), from the parsers."""
    found = []
    for line, parser in parsers(build_parser(), "slam-predict"):
        if not parser._subparsers:
            found.append(line.removeprefix("slam-predict").strip())
    return [c for c in found if c]


def table_rows(text: str) -> list[str]:
    """The first cell of each row of the "## Commands" table, without its backticks."""
    section = text.split("## Commands", 1)[1].split("\n## ", 1)[0]
    return [m.group(1) for m in re.finditer(r"^\| `([^`]+)`", section, re.M)]


def test_every_subcommand_has_a_row():
    rows = table_rows((ROOT / "docs" / "usage.md").read_text(encoding="utf-8"))
    commands = leaf_commands()
    assert len(commands) > 15
    missing = [c for c in commands
               if not any(r == c or r.startswith(c + " ") for r in rows)]
    assert not missing, f"docs/usage.md's command table lacks {missing}"


USAGE_COMMANDS = shown_commands((ROOT / "docs" / "usage.md").read_text(encoding="utf-8"))


def test_the_usage_examples_show_output():
    assert any("--robot" in c for c, _ in USAGE_COMMANDS)
    assert any("--simulate" in c for c, _ in USAGE_COMMANDS)


@pytest.mark.parametrize("command, output", command_params(USAGE_COMMANDS))
def test_the_usage_output_is_what_the_command_prints(command, output, scratch):
    assert_prints(command, output)
