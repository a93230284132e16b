"""`slam beside`: a back-end replayed over collected routes (their sensor logs) and measured like
a collected run. The reference: GMapping beside its own route repeats that run's in-loop SLAM
trajectory and error."""
import copy
import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from slam_predict.cli.main import main
from slam_predict.collect import beside
from slam_predict.collect.batch import RunSpec
from slam_predict.collect.episode import run_episode
from slam_predict.collect.settings import SLAM_SETTINGS, load_settings
from slam_predict.errors import InputError
from slam_predict.formats.tum import read_tum

ROOT = Path(__file__).resolve().parents[2]
TINY = ROOT / "worlds" / "tiny.world"


def route_settings():
    s = load_settings()
    s.slam.params = dataclasses.replace(s.slam.params, particles=6)
    s.stop = dataclasses.replace(s.stop, max_sim_time_s=20.0, small_interval_s=30.0)
    s.sensor_logs = True
    return s


def karto_settings(chain):
    karto = load_settings(SLAM_SETTINGS["karto"])
    karto.slam.params = dataclasses.replace(karto.slam.params, scan_gate="async")
    return dataclasses.replace(copy.deepcopy(chain), slam=karto.slam, compute=karto.compute)


@pytest.fixture(scope="module")
def routes(tmp_path_factory):
    root = tmp_path_factory.mktemp("routes")
    settings = route_settings()
    record = run_episode(RunSpec(str(TINY), "tiny", 0, 5, str(root / "tiny" / "run_000")),
                         settings)
    (root / "tiny" / "no_log").mkdir()   # not a run folder: ignored
    return root, settings, record


def poses(path: Path) -> np.ndarray:
    return np.asarray(read_tum(path)[1])


def test_gmapping_beside_its_own_route_repeats_the_run(routes, tmp_path):
    root, settings, record = routes
    out = tmp_path / "beside"
    assert beside.beside_campaign(root, settings, out) == 1
    mine = json.loads((out / "tiny" / "run_000" / "run.json").read_text())
    # the in-loop SLAM pose of every step, again (positions to the bit; the headings through
    # the bag's quaternions, and the error with them, to round-off)
    mine_poses, loop_poses = (poses(f / "tiny" / "run_000" / "slam.tum") for f in (out, root))
    assert mine_poses.shape == loop_poses.shape and len(loop_poses) > 100
    assert np.array_equal(mine_poses[:, :2], loop_poses[:, :2])
    assert np.allclose(mine_poses[:, 2], loop_poses[:, 2], rtol=0, atol=1e-12)
    assert mine["metric"]["trans_mean"] == pytest.approx(record["metric"]["trans_mean"],
                                                         rel=1e-9)
    assert mine["metric"]["rot_mean"] == pytest.approx(record["metric"]["rot_mean"], rel=1e-9)
    assert mine["map_coverage"] == pytest.approx(record["coverage"], abs=1e-12)
    assert mine["route"]["run"] == "tiny/run_000" and mine["route"]["slam"] == "gmapping"
    for key in ("world", "seed", "sensor", "coverage", "distance_m", "stop_reason"):
        assert mine[key] == record[key]


def test_karto_beside_a_route_is_a_resumable_campaign(routes, tmp_path):
    root, settings, record = routes
    karto = karto_settings(settings)
    out = tmp_path / "beside"
    lines = []
    assert beside.beside_campaign(root, karto, out, progress=lines.append) == 1
    mine = json.loads((out / "tiny" / "run_000" / "run.json").read_text())
    assert mine["slam"]["type"] == "karto" and "karto" in mine["config_hashes"]
    assert mine["route"]["config_hashes"] == record["config_hashes"]
    assert mine["scans_processed"] > 3 and "slam_async" in mine
    assert 0 < mine["metric"]["trans_mean"] < 0.5 and mine["metric"]["poses"] > 100
    assert lines == [f"tiny/run_000: karto ε_t {mine['metric']['trans_mean']:.3f} m, the route's "
                     f"gmapping {record['metric']['trans_mean']:.3f} m"]
    summary = (out / "summary.csv").read_text().splitlines()
    assert len(summary) == 2 and summary[1].startswith("tiny,1,")
    assert beside.beside_campaign(root, karto, out) == 0   # resumed: nothing left to replay
    with pytest.raises(InputError, match="other settings"):
        beside.beside_campaign(root, settings, out)      # GMapping into Karto's folder


def test_a_back_end_on_another_chain_is_refused(routes, tmp_path):
    root, settings, _ = routes
    other = karto_settings(settings)
    other.stop = dataclasses.replace(other.stop, max_sim_time_s=30.0)
    with pytest.raises(InputError, match="stop differ"):
        beside.beside_campaign(root, other, tmp_path / "beside")
    assert not (tmp_path / "beside").exists()


def test_cli_errors_are_one_line_and_exit_2(routes, tmp_path, capsys):
    root, _, _ = routes
    empty = tmp_path / "empty"
    (empty / "tiny" / "run_000").mkdir(parents=True)
    (empty / "tiny" / "run_000" / "run.json").write_text("{}")
    karto = str(SLAM_SETTINGS["karto"])
    assert main(["slam", "beside", str(empty), "--settings", karto,
                 "--out", str(tmp_path / "o")]) == 2
    assert "no collected run with a sensor log" in capsys.readouterr().err
    # the shipped Karto settings are another chain than the routes' (20 s runs)
    assert main(["slam", "beside", str(root), "--settings", karto,
                 "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "differ from the chain" in err


def test_the_pairing_bench_puts_both_errors_side_by_side(routes, tmp_path, capsys):
    import sys
    sys.path.insert(0, str(ROOT / "bench"))
    import bench_beside_compare

    root, settings, record = routes
    out = tmp_path / "beside"
    beside.beside_campaign(root, karto_settings(settings), out)
    mine = json.loads((out / "tiny" / "run_000" / "run.json").read_text())
    assert bench_beside_compare.main([str(root), str(out)]) == 0
    row = [line for line in capsys.readouterr().out.splitlines() if line.startswith("| tiny")]
    g, k = record["metric"]["trans_mean"], mine["metric"]["trans_mean"]
    assert len(row) == 1 and f"| {g:.3f} | {k:.3f} | {k / g:.2f} |" in row[0]
    assert bench_beside_compare.main([str(out), str(root)]) == 2   # routes and replay swapped


def test_karto_beside_a_karto_route_repeats_that_run(tmp_path):
    """Karto's async node replayed beside a route Karto itself drove gives that run again: the
    same scans dropped, the same published poses, the same error."""
    settings = karto_settings(route_settings())
    root = tmp_path / "routes"
    record = run_episode(RunSpec(str(TINY), "tiny", 0, 7, str(root / "tiny" / "run_000")),
                         settings)
    out = tmp_path / "beside"
    assert beside.beside_campaign(root, settings, out) == 1
    mine = json.loads((out / "tiny" / "run_000" / "run.json").read_text())
    assert mine["slam_async"] == record["slam_async"]
    assert mine["metric"]["trans_mean"] == pytest.approx(record["metric"]["trans_mean"],
                                                         rel=1e-9)
    mine_poses, loop_poses = (poses(f / "tiny" / "run_000" / "slam.tum") for f in (out, root))
    assert np.array_equal(mine_poses[:, :2], loop_poses[:, :2])
