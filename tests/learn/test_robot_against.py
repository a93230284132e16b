"""A robot-aware model's leave-one-building-out predictions scored against another table
(learn/robot/against.py), and the `fidelity --loo-runs` options."""
from __future__ import annotations

import pytest

from slam_predict.errors import InputError
from slam_predict.learn.robot.against import leave_one_building_out_against
from slam_predict.learn.robot.models import fit_component

from . import robot_synthetic as syn


@pytest.fixture(scope="module")
def synthetic(tmp_path_factory):
    folder = tmp_path_factory.mktemp("robots_against")
    worlds, robots, _ = syn.campaign(folder / "data", n_worlds=8, n_configs=4)
    data = syn.load(folder / "data", worlds)
    config = syn.fast_config(models=["elasticnet"])
    return data.tables(config.plan_features), config


def test_each_building_is_predicted_by_a_refit_on_the_other_buildings(synthetic):
    tables, config = synthetic
    worlds = sorted(set(tables.point_world))
    truth = {w: {"trans_mean": 0.5, "rot_mean": 0.02} for w in worlds[1:]}
    rows = leave_one_building_out_against(tables, config, {"trans_mean": "elasticnet"}, "c02",
                                          truth)
    assert [r["world"] for r in rows] == worlds[1:]
    for r in rows:
        # the reference: the points of every other building, picked one by one
        others = [i for i, w in enumerate(tables.point_world) if w != r["world"]]
        (point,) = [i for i, (w, c) in enumerate(zip(tables.point_world, tables.point_config,
                                                     strict=True))
                    if w == r["world"] and c == "c02"]
        model = fit_component(tables.subset(others), "trans_mean", "elasticnet", config)
        assert r["prediction"] == pytest.approx(model.predict(tables.point_X[[point]])[0])
        assert r["ours"] == tables.point_y["trans_mean"][point] and r["y"] == 0.5
        assert r["pct_error"] == pytest.approx(abs(r["prediction"] - 0.5) / 0.5)
        assert r["covered"] == (r["low"] <= 0.5 <= r["high"])


def test_a_robot_without_points_in_the_other_table_is_refused(synthetic):
    tables, config = synthetic
    with pytest.raises(InputError, match="no building has both a point of configuration "
                                         "'seed'"):
        leave_one_building_out_against(tables, config, {"trans_mean": "elasticnet"}, "seed",
                                       {w: {"trans_mean": 1.0} for w in tables.point_world})


@pytest.mark.parametrize("extra, message", [
    (["--loo-runs", "DATA"], "--loo-runs needs --worlds DIR"),
    (["--loo-runs", "DATA", "--worlds", "W", "--jobs", "0"], "--jobs"),
])
def test_fidelity_loo_runs_options_are_checked(extra, message, tmp_path, capsys):
    from slam_predict.cli.main import main

    (tmp_path / "stats.csv").write_text("dataset\n")
    code = main(["fidelity", str(tmp_path), "--thesis", str(tmp_path / "stats.csv"), *extra])
    lines = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and message in lines[0], lines


def test_loo_runs_and_loo_dataset_exclude_each_other(tmp_path, capsys):
    from slam_predict.cli.main import main

    with pytest.raises(SystemExit) as exc:
        main(["fidelity", str(tmp_path), "--thesis", "t.csv", "--loo-runs", "D",
              "--loo-dataset", "x.csv"])
    assert exc.value.code == 2
    assert "--loo-dataset: not allowed with argument --loo-runs" in capsys.readouterr().err
