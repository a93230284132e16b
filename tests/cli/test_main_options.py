"""Global options of ``slam-predict``: accepted before and after the subcommand."""
from __future__ import annotations

import pytest

from slam_predict.cli.main import build_parser


@pytest.mark.parametrize("argv,level", [(["predict", "x.png"], 0),
                                        (["-v", "predict", "x.png"], 1),
                                        (["predict", "-v", "x.png"], 1),
                                        (["predict", "x.png", "-vv"], 2),
                                        (["-vv", "report", "d"], 2)])
def test_verbose_before_or_after_the_subcommand(argv, level):
    assert build_parser().parse_args(argv).verbose == level


def test_help_shows_defaults_not_said_already():
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command").choices["collect"]
    text = sub.format_help()
    assert "(default: " in text
    assert "(default: None)" not in text and "(default: False)" not in text
