"""bench/bench_gmapping_diff.py --runs (bench/gmapping_diff/collected_runs.py) on a real
collected run (tiny world, sensor logs on), no upstream needed: run discovery, the recorded
parameters, the run's own errors scored like both sides of the check, the per-run table and its
median."""
import dataclasses
import importlib.util
from pathlib import Path

import numpy as np
import pytest

from slam_predict.collect.batch import RunSpec
from slam_predict.collect.episode import run_episode
from slam_predict.collect.settings import load_settings
from slam_predict.slam import runner
from slam_predict.slam.gmapping.params import params_to_dict

ROOT = Path(__file__).resolve().parents[2]
BENCH = ROOT / "bench" / "bench_gmapping_diff.py"


def _bench():
    spec = importlib.util.spec_from_file_location("bench_gmapping_diff", BENCH)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    folder = tmp_path_factory.mktemp("diffruns")
    settings = load_settings()
    settings.slam.params = dataclasses.replace(settings.slam.params, particles=6)
    settings.stop = dataclasses.replace(settings.stop, max_sim_time_s=20.0, small_interval_s=30.0)
    settings.sensor_logs = True
    run = folder / "tiny" / "run_000"
    record = run_episode(RunSpec(str(ROOT / "worlds" / "tiny.world"), "tiny", 0, 5, str(run)),
                         settings)
    (folder / "tiny" / "not_a_run").mkdir()
    return folder, run, record


def test_runs_are_found_in_campaigns_and_named_by_world(campaign):
    bench = _bench()
    folder, run, _ = campaign
    assert bench.collected.find_runs([folder]) == [run]
    assert bench.collected.find_runs([run]) == [run]
    assert bench.collected.run_name(run) == "tiny-run_000"
    with pytest.raises(SystemExit, match="no run folder"):
        bench.collected.find_runs([folder / "tiny" / "not_a_run"])


def test_a_run_is_replayed_with_its_recorded_parameters(campaign):
    bench = _bench()
    _, run, record = campaign
    data, params, short = bench.load(str(run), None, {})
    assert short == "tiny-run_000" and len(data) == record["sensor_logs"]["scans"]
    assert params_to_dict(params) == record["sensor_logs"]["gmapping"]
    assert params.particles == 6
    _, params, _ = bench.load(str(run), None, {"particles": 3})
    assert params.particles == 3


def test_in_loop_errors_score_the_in_loop_trajectory_like_both_sides(campaign):
    bench = _bench()
    _, run, record = campaign
    data, params, _ = bench.load(str(run), None, {})
    own = bench.collected.in_loop_errors(run, data)
    assert own["loop_trans_m"] == record["metric"]["trans_mean"]
    assert own["slam_scans"] == record["sensor_logs"]["slam_scans"]
    # the replay with the run's own generator is the in-loop run: the bench scores it the same
    recorded = runner.recorded_run(run / "sensors.log.gz")
    result = runner.run(data, "gmapping", params, recorded.seed, rng=recorded.rng())
    error = bench.error_of(data, result.indices, result.poses)
    # (slam_scans.tum holds the poses as text: equal up to its round-off)
    assert own["scans_trans_m"] == pytest.approx(error["trans_mean_m"], rel=1e-9)
    assert own["scans_rot_deg"] == pytest.approx(error["rot_mean_deg"], rel=1e-9)
    assert own["scans_trans_m"] > 0.0
    # the bench's own loop over the port (bench_gmapping_rng.py uses it; it draws from the
    # generator it is given, i.e. the numpy stream here) gives the same run as the runner
    result = runner.run(data, "gmapping", dataclasses.replace(params, random_stream="numpy"),
                        recorded.seed, rng=recorded.rng())
    port = bench.run_port(data, params, recorded.rng())
    assert port["indices"] == result.indices.tolist()
    assert np.array_equal(np.array(port["poses"]), result.poses)


def test_match_times_refuses_stamps_without_a_scan():
    match = _bench().collected.match_times
    times = np.array([0.0, 0.1, 0.2, 0.3])
    assert match(times, np.array([0.0, 0.2, 0.3])).tolist() == [0, 2, 3]
    with pytest.raises(ValueError, match="nearest scan"):
        match(times, np.array([0.15]))


def _record(name, side, seed, trans):
    return {"log": name, "side": side, "seed": seed,
            "error": {"trans_mean_m": trans, "rot_mean_deg": 1.0}}


def test_runs_table_gives_each_ratio_and_their_median():
    bench = _bench()
    errors = {"a": ([0.2, 0.2], [0.1, 0.1]), "b": ([0.1, 0.1], [0.1, 0.1]),
              "c": ([0.3, 0.3], [0.6, 0.6])}
    records = [_record(name, side, seed, e)
               for name, pair in errors.items()
               for side, values in zip(("ours", "real"), pair, strict=True)
               for seed, e in enumerate(values)]
    own = {"loop_trans_m": 0.1, "loop_rot_deg": 0.5, "scans_trans_m": 0.1, "scans_rot_deg": 0.5}
    text = bench.collected.runs_table(records, {n: own for n in errors}, bench.bootstrap_ratio)
    rows = [line.split(" | ") for line in text.splitlines()[2:5]]
    assert [(r[0], r[4], r[5]) for r in rows] == [("| a", "2.00", "2.00–2.00"),
                                                  ("| b", "1.00", "1.00–1.00"),
                                                  ("| c", "0.50", "0.50–0.50")]
    assert "median ratio over 3 runs: 1.00 (min 0.50, max 2.00)" in text


def test_a_delayed_run_gives_both_sides_only_the_scans_its_gmapping_was_handed(tmp_path):
    from slam_predict.slam.compute_delay import ComputeDelayConfig

    settings = load_settings()
    settings.slam.params = dataclasses.replace(settings.slam.params, particles=6)
    settings.stop = dataclasses.replace(settings.stop, max_sim_time_s=30.0, small_interval_s=30.0)
    settings.sensor_logs = True
    settings.compute = ComputeDelayConfig(model="cost", scan_s=0.35, rebuild_s_per_map_cell=2e-8)
    run = tmp_path / "tiny" / "run_000"
    record = run_episode(RunSpec(str(ROOT / "worlds" / "tiny.world"), "tiny", 0, 5, str(run)),
                         settings)
    handled = record["slam_compute"]["scans_handled"]
    assert handled < record["sensor_logs"]["scans"]
    bench = _bench()
    bench.HANDED_DIR = str(tmp_path / "handed")
    data, params, short = bench.load(str(run), None, {})
    assert len(data) == handled and (tmp_path / "handed" / f"{short}.txt").is_file()
    # fed without a delay, the handed scans give the in-loop trajectory (slam_scans.tum)
    recorded = runner.recorded_run(run / "sensors.log.gz")
    result = runner.run(data, "gmapping", params, recorded.seed, rng=recorded.rng())
    own = bench.collected.in_loop_errors(run, data)
    error = bench.error_of(data, result.indices, result.poses)
    assert own["scans_trans_m"] == pytest.approx(error["trans_mean_m"], rel=1e-9)
    assert own["slam_scans"] == len(result.indices)
