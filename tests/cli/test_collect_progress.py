"""Progress of `collect` with its runs in this process: a bar of runs and, inside each run, a
bar of simulated seconds; --no-progress shows neither."""
from __future__ import annotations

from robot_runs import TINY, short_settings

from slam_predict.cli.main import main


def test_a_run_shows_its_simulated_seconds(tmp_path, capsys):
    settings = short_settings(tmp_path)
    assert main(["collect", str(TINY), "--runs", "1", "--out", str(tmp_path / "a"),
                 "--settings", str(settings)]) == 0
    err = capsys.readouterr().err
    assert "tiny run 0" in err and "sim s" in err and "/25 " in err, err
    assert main(["collect", str(TINY), "--runs", "1", "--out", str(tmp_path / "b"),
                 "--settings", str(settings), "--no-progress"]) == 0
    assert "sim s" not in capsys.readouterr().err
