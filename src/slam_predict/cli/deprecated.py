"""Old option spellings kept working for one release, with a warning that names the new one."""
from __future__ import annotations

import argparse
import sys


def add_renamed_option(parser, old: str, new_action: argparse.Action) -> None:
    """Accept ``old`` as a hidden spelling of the option ``new_action`` (already added to
    ``parser`` or one of its groups): same value, same destination, and one line on stderr
    saying which spelling to use."""
    parser.add_argument(old, dest=new_action.dest, nargs=new_action.nargs,
                        type=new_action.type, metavar=new_action.metavar,
                        action=_renamed(new_action.option_strings[0]), help=argparse.SUPPRESS)


def _renamed(new: str) -> type[argparse.Action]:
    class Renamed(argparse.Action):
        def __call__(self, parser, namespace, values, option_string=None):
            print(f"{parser.prog}: warning: {option_string} is deprecated and will be removed "
                  f"in the next release; use {new}", file=sys.stderr)
            setattr(namespace, self.dest, values)
    return Renamed
