"""Entry point of ``slam-predict``: builds the parser from the subcommand modules, runs one.

Each subcommand module in :mod:`slam_predict.cli` defines ``NAME``, ``HELP``,
``add_arguments(parser)`` and ``run(args) -> int``; modules keep heavy imports inside ``run`` so
``--help`` stays fast. Known errors (:class:`InputError`) become one line on stderr and exit 2.
"""
from __future__ import annotations

import argparse
import importlib
import logging
import sys

from slam_predict import __version__
from slam_predict.errors import InputError

# Subcommand modules, in the order --help lists them.
SUBCOMMANDS = (
    "worlds",
    "sim",
    "slam",
    "explore",
    "features",
    "collect",
    "design",
    "fidelity",
    "metric",
    "learn",
    "predict",
    "report",
)


class HelpFormatter(argparse.HelpFormatter):
    """argparse's formatter that appends each option's default to its help, unless the default
    is empty (None, False, an empty list) or the help already says it."""

    def _get_help_string(self, action: argparse.Action) -> str:
        text = action.help or ""
        default = action.default
        if ("%(default)" in text or "default" in text.lower() or not action.option_strings
                or default in (None, False, argparse.SUPPRESS) or default == []
                or isinstance(action, argparse._VersionAction)):
            return text
        return f"{text} (default: %(default)s)"


def global_options(top: bool) -> argparse.ArgumentParser:
    """Options accepted before and after the subcommand (``slam-predict -v predict`` and
    ``slam-predict predict -v``); after it they only override what was given before."""
    options = argparse.ArgumentParser(add_help=False)
    options.add_argument("-v", "--verbose", action="count",
                         default=0 if top else argparse.SUPPRESS,
                         help="more log output (-v info, -vv debug)")
    return options


def build_parser() -> argparse.ArgumentParser:
    """The full argument parser with every subcommand."""
    parser = argparse.ArgumentParser(
        prog="slam-predict", parents=[global_options(top=True)], formatter_class=HelpFormatter,
        description="Predict GMapping's localization error in a building from its floor plan.")
    parser.add_argument("--version", action="version", version=f"slam-predict {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    after = global_options(top=False)
    for name in SUBCOMMANDS:
        module = importlib.import_module(f"slam_predict.cli.{name}_cmd")
        child = sub.add_parser(name, help=module.HELP, description=module.HELP,
                               parents=[after], formatter_class=HelpFormatter)
        module.add_arguments(child)
        child.set_defaults(_run=module.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; returns the process exit code (0 ok, 2 bad input, 1 other failure)."""
    try:
        parser = build_parser()   # imports the SLAM back-end plugins (map-source choices)
    except InputError as exc:
        print(f"slam-predict: error: {exc.one_line()}", file=sys.stderr)
        return exc.exit_code
    args = parser.parse_args(argv)
    level = (logging.WARNING, logging.INFO, logging.DEBUG)[min(args.verbose, 2)]
    logging.basicConfig(level=level, format="%(levelname)s %(name)s: %(message)s")
    if not getattr(args, "_run", None):
        parser.print_help()
        return 2
    try:
        return int(args._run(args) or 0)
    except InputError as exc:
        print(f"slam-predict {args.command}: error: {exc.one_line()}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        print(f"slam-predict {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
