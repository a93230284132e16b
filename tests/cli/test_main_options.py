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


def test_a_renamed_option_still_works_with_a_warning(capsys):
    parser = build_parser()
    old = parser.parse_args(["report", "d", "--models", "models"])
    assert old.models_dir == "models"
    assert "--models is deprecated" in capsys.readouterr().err
    new = parser.parse_args(["design", "w.world", "--out", "d.yaml", "--angle-step", "0.25"])
    assert new.angle_step == 0.25 and capsys.readouterr().err == ""
    assert parser.parse_args(["design", "w.world", "--out", "d.yaml",
                              "--resolution", "0.3"]).angle_step == 0.3
    assert "use --angle-step" in capsys.readouterr().err
