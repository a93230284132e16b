"""Leave-one-building-out predictions scored against another table (learn/against.py)."""
from __future__ import annotations

import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.learn import against
from tests.learn.conftest import synthetic_dataset, tiny_config


def ordinary_least_squares_loo(x: np.ndarray, y: np.ndarray, i: int) -> float:
    """The straight line through every point but i, evaluated at x[i] (numpy's polyfit)."""
    keep = np.arange(len(x)) != i
    slope, intercept = np.polyfit(x[keep], y[keep], 1)
    return slope * x[i] + intercept


def test_predictions_are_refitted_without_the_building_and_scored_against_the_other_table():
    data = synthetic_dataset(n=12, seed=3)
    length = data.X[:, data.feature_names.index("length")]
    ours = data.target("trans_mean")
    truth = {w: {"trans_mean": 1.25 * ours[i]} for i, w in enumerate(data.worlds) if i % 3}
    rows = against.leave_one_out_against(data, tiny_config(), {"trans_mean": "single:length"},
                                         truth)
    assert [r["world"] for r in rows] == [w for w in data.worlds if w in truth]
    for r in rows:
        i = data.worlds.index(r["world"])
        assert r["prediction"] == pytest.approx(ordinary_least_squares_loo(length, ours, i))
        assert r["ours"] == ours[i] and r["y"] == truth[r["world"]]["trans_mean"]
        assert r["pct_error"] == pytest.approx(abs(r["prediction"] - r["y"]) / r["y"])
    (s,) = against.summary(rows)
    assert s["n_buildings"] == len(truth)
    assert s["chain_median_pct_error"] == pytest.approx(0.2)     # |x − 1.25x| / 1.25x
    assert s["median_pct_error"] == pytest.approx(np.median([r["pct_error"] for r in rows]))
    text = against.markdown(rows, "tiny", "the other table")
    assert "bar ≤ 12 %" in text and rows[0]["world"] in text


def test_a_card_without_a_model_or_configuration_is_refused():
    with pytest.raises(InputError, match="no rot_mean model"):
        against.card_models({"name": "x", "components": {"trans_mean": {"best": "single:a"}}},
                            ["trans_mean", "rot_mean"])
    with pytest.raises(InputError, match="not a plan-only model"):
        against.card_learning_config({"name": "own-robots"})


def test_fidelity_cli_scores_a_shipped_models_kind_against_the_thesis_table(
        tiny_models, tmp_path, capsys):
    """`fidelity --loo-dataset D --loo-model M` appends the per-building table and the bar."""
    import json

    from slam_predict.cli.main import main
    from slam_predict.learn.dataset import write_dataset

    data = synthetic_dataset()
    write_dataset(data, tmp_path / "own.csv")
    thesis = tmp_path / "stats.csv"
    thesis.write_text("dataset, Voronoi distance, Voronoi rotation, totalLen, totalRot, "
                      "transError.mean.mean, transError.mean.std, rotError.mean.mean, "
                      "rotError.mean.std\n" + "".join(
                          f"{w}, 1, 1, 50, 1, {1.1 * data.target('trans_mean')[i]}, 0.01, "
                          f"{data.target('rot_mean')[i]}, 0.001\n"
                          for i, w in enumerate(data.worlds[:6])))
    run = tmp_path / "camp" / data.worlds[0] / "run_000"
    run.mkdir(parents=True)
    run.joinpath("run.json").write_text(json.dumps(
        {"metric": {"trans_mean": 0.3, "rot_mean": 0.01}, "distance_m": 50.0,
         "coverage": 1.0, "free_area_m2": 100.0}))
    argv = ["fidelity", str(tmp_path / "camp"), "--thesis", str(thesis),
            "--loo-dataset", str(tmp_path / "own.csv"),
            "--loo-model", str(tiny_models / "tiny-realistic")]
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "Leave-one-building-out predictions of tiny-realistic" in text
    assert text.count("| trans_mean |") == 6 and "bar ≤ 12 %" in text
    assert main(argv[:-1] + [str(tmp_path / "nowhere")]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1


def test_a_dataset_too_small_to_leave_one_out_is_refused_naming_it():
    data = synthetic_dataset(n=against.MIN_BUILDINGS - 1, seed=1)
    truth = {w: {"trans_mean": 1.0} for w in data.worlds}
    with pytest.raises(InputError, match=r"own\.csv: 3 building\(s\); .* at least 4"):
        against.leave_one_out_against(data, tiny_config(), {"trans_mean": "single:length"},
                                      truth, source="own.csv")
    smallest = synthetic_dataset(n=against.MIN_BUILDINGS, seed=1)
    rows = against.leave_one_out_against(smallest, tiny_config(),
                                         {"trans_mean": "single:length"},
                                         {w: {"trans_mean": 1.0} for w in smallest.worlds})
    assert len(rows) == against.MIN_BUILDINGS
