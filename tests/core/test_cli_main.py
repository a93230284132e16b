"""The CLI entry: help lists subcommands; InputError becomes one line and exit code 2."""
import subprocess
import sys

from slam_predict.cli import main as cli


def test_help_lists_every_subcommand(capsys):
    parser = cli.build_parser()
    text = parser.format_help()
    for name in cli.SUBCOMMANDS:
        assert name in text


def test_no_command_prints_help_and_exits_2(capsys):
    assert cli.main([]) == 2
    assert "usage: slam-predict" in capsys.readouterr().out


def test_console_script_runs():
    out = subprocess.run([sys.executable, "-m", "slam_predict.cli.main", "--version"],
                         capture_output=True, text=True, check=True)
    assert out.stdout.startswith("slam-predict ")
