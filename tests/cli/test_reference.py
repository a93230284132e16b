"""docs/reference/cli.md is the generation of the parsers (not stale), and it covers every
subcommand and visible option, without the deprecated spellings."""
from __future__ import annotations

import argparse
import sys

import pytest

from slam_predict.cli.main import SUBCOMMANDS, build_parser
from slam_predict.cli.reference import parsers, reference


def test_the_committed_reference_is_the_generated_one(root):
    committed = (root / "docs" / "reference" / "cli.md").read_text(encoding="utf-8")
    python = "Generated with Python {}.{} ".format(*sys.version_info[:2])
    if python not in committed:
        pytest.skip("docs/reference/cli.md was generated with another Python (argparse's "
                    "layout differs)")
    assert committed == reference(), (
        "docs/reference/cli.md is stale: python -m slam_predict.cli.reference > "
        "docs/reference/cli.md")


def test_every_command_and_visible_option_is_there():
    text = reference()
    for name in SUBCOMMANDS:
        assert f"\n## slam-predict {name}\n" in text
    for command, parser in parsers(build_parser(), "slam-predict"):
        assert f"\n## {command}\n" in text
        for action in parser._actions:
            if action.option_strings and action.help != argparse.SUPPRESS and action.dest != "help":
                assert f"`{action.option_strings[-1]}`" in text, (command, action.dest)
    report = text.split("\n## slam-predict report\n")[1].split("\n## ")[0]
    assert "`--models-dir`" in report and "`--models`" not in report
