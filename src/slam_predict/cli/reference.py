"""The command-line reference (docs/reference/cli.md), generated from the parsers themselves.

``python -m slam_predict.cli.reference > docs/reference/cli.md`` writes it; a test compares the
file with a fresh generation, so it cannot go stale. Every subcommand (and action) gets its
description, its usage line and a table of its arguments: names, value, default, meaning.
Deprecated spellings (hidden from ``--help``) are left out.
"""
from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Iterator

WIDTH = 100   # columns of the usage lines, fixed so the file is the same on every machine
HEADER = """# Command-line reference

Every `slam-predict` subcommand and option, generated from the parsers by
`python -m slam_predict.cli.reference > docs/reference/cli.md` (tests/cli/test_reference.py
fails when this file is stale). `slam-predict COMMAND --help` prints the same. Options given
before the subcommand (`-v`) are accepted after it too. Old option spellings that still work
for one release with a warning are not listed. Generated with Python {python} (argparse lays
out usage lines a little differently from version to version).
"""


def parsers(parser: argparse.ArgumentParser,
            name: str) -> Iterator[tuple[str, argparse.ArgumentParser]]:
    """(command line, parser) of ``parser`` and of every subcommand below it, depth first."""
    yield name, parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for child, sub in action.choices.items():
                yield from parsers(sub, f"{name} {child}")


def _cell(text: str) -> str:
    return " ".join(str(text).split()).replace("|", "\\|")


def _value(action: argparse.Action) -> str:
    if action.nargs == 0:
        return ""
    if action.choices and not isinstance(action, argparse._SubParsersAction):
        return "{" + ", ".join(map(str, action.choices)) + "}"
    metavar = action.metavar or action.dest.upper()
    return " ".join(metavar) if isinstance(metavar, tuple) else str(metavar)


def _default(action: argparse.Action) -> str:
    default = action.default
    if action.nargs == 0 or default in (None, argparse.SUPPRESS) or default == []:
        return ""
    return f"`{default}`"


def argument_rows(parser: argparse.ArgumentParser) -> list[str]:
    """One Markdown table row per visible argument of ``parser``."""
    formatter = parser._get_formatter()
    rows = []
    for action in parser._actions:
        if action.help == argparse.SUPPRESS or isinstance(action, argparse._HelpAction):
            continue
        if isinstance(action, argparse._SubParsersAction):
            names = ", ".join(f"`{c}`" for c in action.choices)
            rows.append(f"| {action.metavar or 'COMMAND'} | {names} | | see below |")
            continue
        names = ", ".join(f"`{s}`" for s in action.option_strings) or (
            f"`{action.metavar or action.dest}`")
        meaning = formatter._expand_help(action) if action.help else ""
        rows.append(f"| {names} | {_cell(_value(action))} | {_cell(_default(action))} | "
                    f"{_cell(meaning)} |")
    return rows


def section(command: str, parser: argparse.ArgumentParser) -> str:
    """The Markdown section of one (sub)command."""
    lines = [f"## {command}", ""]
    if parser.description:
        lines += [_cell(parser.description), ""]
    lines += ["```", parser.format_usage().strip(), "```", ""]
    rows = argument_rows(parser)
    if rows:
        lines += ["| argument | value | default | meaning |", "|---|---|---|---|", *rows, ""]
    return "\n".join(lines)


def reference() -> str:
    """The whole reference, as Markdown."""
    from slam_predict.cli.main import build_parser

    previous = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = str(WIDTH)
    try:
        root = build_parser()
        body = [section(name, parser) for name, parser in parsers(root, "slam-predict")]
    finally:
        if previous is None:
            os.environ.pop("COLUMNS", None)
        else:
            os.environ["COLUMNS"] = previous
    python = "{}.{}".format(*sys.version_info[:2])
    return HEADER.format(python=python) + "\n" + "\n".join(body)


if __name__ == "__main__":
    sys.stdout.write(reference())
