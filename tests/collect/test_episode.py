"""Episodes with GMapping in the loop: a record that reloads, determinism, the stop rule.

CI runs short episodes on a tiny world with few particles; the full office_500 episode
(MSE stop, coverage ≥ 90 %) is marked slow.
"""
import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from slam_predict.collect.batch import RunSpec
from slam_predict.collect.episode import full_extent_grid, run_episode
from slam_predict.collect.record import FILES, SCHEMA_VERSION, _plain, load_record, without_timing
from slam_predict.collect.settings import load_settings
from slam_predict.slam import OccupancyGrid

ROOT = Path(__file__).resolve().parents[2]
TINY = ROOT / "worlds" / "tiny.world"
if not TINY.exists():
    TINY = ROOT / "tests" / "data" / "world_map" / "tiny.world"


def quick_settings(max_sim_time=60.0, particles=6):
    settings = load_settings()
    settings.slam.params = dataclasses.replace(settings.slam.params, particles=particles)
    settings.stop = dataclasses.replace(settings.stop, max_sim_time_s=max_sim_time,
                                        small_interval_s=30.0)
    return settings


def run(tmp_path, name, seed=3, **kwargs):
    spec = RunSpec(str(TINY), "tiny", 0, seed, str(tmp_path / name / "tiny" / "run_000"))
    return run_episode(spec, quick_settings(**kwargs)), Path(spec.out_dir)


def test_full_extent_grid_places_the_map():
    extent = (-100.0, -100.0, 100.0, 100.0)   # slam_gmapping's default xmin..ymax, m
    data = np.zeros((3, 4), np.int8)
    data[0, 0] = 100
    canvas = full_extent_grid(OccupancyGrid(data, 0.05, (1.0, -2.0)), extent)
    assert canvas.shape == (4000, 4000)
    row, col = int(round((-2.0 + 100) / 0.05)), int(round((1.0 + 100) / 0.05))
    assert canvas[row, col] == 100 and (canvas == 0).sum() == 11
    assert (canvas == -1).sum() == 4000 ** 2 - 12


def test_short_episode_record_reloads_and_is_deterministic(tmp_path, run_record_keys):
    first, folder = run(tmp_path, "a")
    second, _ = run(tmp_path, "b")
    for name in FILES:
        assert (folder / name).is_file(), name
    record, traj = load_record(folder)
    assert record == json.loads(json.dumps({"schema": SCHEMA_VERSION, **first}, default=_plain))
    assert len(traj.t) == int(round(first["sim_duration_s"] / 0.1))
    assert np.allclose(np.diff(traj.t), 0.1)
    assert without_timing(first) == without_timing(second)
    assert set(first) - {"sensor_logs"} == run_record_keys   # the builder the ROS path uses too
    assert (folder / "slam.tum").read_text() == (tmp_path / "b/tiny/run_000/slam.tum").read_text()
    metric = first["metric"]
    assert 0 < metric["trans_mean"] < 0.5 and metric["n"] >= 2
    assert first["distance_m"] > 1.0 and first["stalls"] == 0
    assert first["stop_reason"] in ("map_converged", "max_sim_time")
    assert first["snapshots"][0]["mse"] is None
    assert first["settings_file"] == "config/collect.yaml"  # portable across clones
    assert first["world_file"] == TINY.relative_to(ROOT).as_posix()


def test_different_seeds_differ(tmp_path):
    a, _ = run(tmp_path, "a", seed=1, max_sim_time=20.0)
    b, _ = run(tmp_path, "b", seed=2, max_sim_time=20.0)
    assert a["odometry_error"] != b["odometry_error"]


@pytest.mark.slow
def test_office_500_episode_converges_with_high_coverage(tmp_path):
    world = ROOT / "worlds" / "office_500.world"
    spec = RunSpec(str(world), "office_500", 0, 7, str(tmp_path / "office_500" / "run_000"))
    record = run_episode(spec)
    assert record["stop_reason"] == "map_converged"
    assert record["coverage"] >= 0.9
    assert record["coverage_swept"] >= 0.9
    reloaded, _ = load_record(Path(spec.out_dir))
    assert reloaded["stop_reason"] == "map_converged"


def test_metric_evaluate_on_the_records_bag_gives_the_records_numbers(tmp_path, capsys):
    """Issue #7: `metric evaluate` on the bag written from a run record (ground truth on a pose
    topic) reproduces the record's own statistics, given the record's metric seed."""
    from slam_predict.cli.main import main
    from slam_predict.collect.record import GT_TOPIC, SLAM_TOPIC

    settings = quick_settings(max_sim_time=30.0)
    settings.bag = True
    spec = RunSpec(str(TINY), "tiny", 0, 5, str(tmp_path / "tiny" / "run_000"))
    record = run_episode(spec, settings)
    bag = Path(spec.out_dir) / "run.bag"
    seed = [str(v) for v in record["metric"]["info"]["seed"]]
    assert main(["metric", "evaluate", "--slam", str(bag), "--slam-topic", SLAM_TOPIC,
                 "--gt", str(bag), "--gt-topic", GT_TOPIC, "--seed", *seed, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    metric = record["metric"]
    assert out["stats"]["trans_abs"]["n"] == metric["n"]
    for ours, theirs in (("trans_mean", ("trans_abs", "mean")), ("trans_std", ("trans_abs", "std")),
                         ("rot_mean", ("rot_abs", "mean")), ("rot_std", ("rot_abs", "std"))):
        assert out["stats"][theirs[0]][theirs[1]] == pytest.approx(metric[ours], rel=1e-9,
                                                                   abs=1e-12)


def test_incremental_published_map_leaves_the_episode_unchanged(tmp_path, monkeypatch):
    """Issue #7 speed-ups keep results: the same seed with the published map rebuilt from
    scratch at every update gives the same record, trajectories, snapshots and map."""
    from slam_predict.slam.gmapping.filter import GMapping

    fast, folder = run(tmp_path, "incremental", seed=4, max_sim_time=45.0)
    monkeypatch.setattr(GMapping, "incremental_map", False)
    full, full_folder = run(tmp_path, "rebuilt", seed=4, max_sim_time=45.0)
    assert without_timing(fast) == without_timing(full)
    for name in ("slam.tum", "ground_truth.tum", "map.pgm", "snapshots/snapshot_01.png"):
        assert (folder / name).read_bytes() == (full_folder / name).read_bytes(), name
