"""docs/reference/cli.md is the generation of the parsers (not stale), and it covers every
subcommand and visible option, without the deprecated spellings."""
from __future__ import annotations

import argparse
import os
import subprocess
import sys

import pytest

from slam_predict.cli.main import SUBCOMMANDS, build_parser
from slam_predict.cli.reference import parsers, reference


def fresh_reference() -> str:
    """The reference generated in a new process: the SLAM back-ends registered by other tests
    (tests/slam/dummy_backend.py) or by SLAM_PREDICT_EXTRA_BACKENDS must not reach it."""
    env = {k: v for k, v in os.environ.items() if k != "SLAM_PREDICT_EXTRA_BACKENDS"}
    done = subprocess.run([sys.executable, "-m", "slam_predict.cli.reference"], env=env,
                          capture_output=True, text=True, check=True)
    return done.stdout


def test_the_committed_reference_is_the_generated_one(root):
    committed = (root / "docs" / "reference" / "cli.md").read_text(encoding="utf-8")
    python = "Generated with Python {}.{} ".format(*sys.version_info[:2])
    if python not in committed:
        pytest.skip("docs/reference/cli.md was generated with another Python (argparse's "
                    "layout differs)")
    assert committed == fresh_reference(), (
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
