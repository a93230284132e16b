"""Every SLAM back-end of ``slam.available()``, plus the test-only ``dummy`` registered here by
importing its module, through the interface, ``slam run``, ``explore`` and ``collect``: the
callers outside ``slam/`` need nothing but the interface (issue #17)."""
import json
import os
import subprocess
import sys
from pathlib import Path

import dummy_backend  # noqa: F401  (registers "dummy", as a user's back-end module would)
import numpy as np
import pytest
from slam_scan import ANGLES, scan_of
from test_interface import drive

from slam_predict import slam
from slam_predict.cli.main import main
from slam_predict.geometry import compose
from slam_predict.slam import LaserGeometry, OccupancyGrid

ROOT = Path(__file__).resolve().parents[2]
TINY = ROOT / "worlds" / "tiny.world"
BACKENDS = slam.available()
# small but valid parameters per back-end (a back-end added later runs with its defaults)
FAST = {"gmapping": {"particles": 4, "xmin": -15.0, "ymin": -15.0, "xmax": 15.0, "ymax": 15.0}}


def test_the_dummy_is_registered_beside_the_shipped_back_ends():
    assert {"gmapping", "dummy"} <= set(BACKENDS)


def fast_params(name):
    return slam.params_from_dict(name, FAST.get(name, {}), "test")


@pytest.mark.parametrize("name", BACKENDS)
def test_interface_contract_on_a_synthetic_drive(name):
    truth, odom = drive(40)
    laser = LaserGeometry(ANGLES, (0.1, 0.0, 0.0), 30.0)
    backend = slam.create(name, params=fast_params(name), laser=laser,
                          rng=np.random.default_rng(1))
    assert backend.name == name and backend.beam_angles.size == laser.beams
    assert backend.map_update_interval > 0.0
    xmin, ymin, xmax, ymax = backend.map_extent
    processed = 0
    for k in range(len(truth)):
        pose = backend.update(odom[k], scan_of(compose(truth[k], laser.pose_in_base)), 0.1 * k)
        if pose is not None:
            processed += 1
            assert np.allclose(pose, compose(backend.map_to_odom(), odom[k]))
    assert processed > 3
    assert np.allclose(backend.pose(), compose(backend.map_to_odom(), odom[-1]))
    numbers, times, poses = backend.trajectory()
    assert len(numbers) == len(times) == len(poses) == processed and poses.shape[1] == 3
    grid = backend.map()
    assert isinstance(grid, OccupancyGrid) and grid.data.dtype == np.int8
    assert set(np.unique(grid.data)) <= {-1, 0, 100} and (grid.data == 100).sum() > 20
    assert grid.origin[0] >= xmin - 1e-9 and grid.origin[1] >= ymin - 1e-9
    assert grid.origin[0] + grid.width * grid.resolution <= xmax + grid.resolution
    assert grid.origin[1] + grid.height * grid.resolution <= ymax + grid.resolution
    assert backend.entropy() >= 0.0 and isinstance(backend.stats(), dict)


@pytest.mark.parametrize("name", BACKENDS)
def test_explore_and_collect_with_every_back_end(name, tmp_path, capsys):
    config = tmp_path / "config"
    config.mkdir()
    for path in (ROOT / "config").glob("*.yaml"):
        if path.name != "gmapping.yaml":
            (config / path.name).write_text(path.read_text())
    (config / f"{name}.yaml").write_text(json.dumps({"type": name, **FAST.get(name, {})}))
    out = tmp_path / "explore"
    assert main(["explore", str(TINY), "--map-source", name, "--seed", "1", "--max-sim-time",
                 "40", "--out", str(out), "--config-dir", str(config)]) == 0
    summary = json.loads((out / "explore.json").read_text())
    assert summary["map_source"] == name and summary["coverage"] > 0.05
    settings = tmp_path / "collect.yaml"
    settings.write_text(f"extends: {ROOT / 'config' / 'collect.yaml'}\n"
                        f"slam: {{type: {name}, params: {config / (name + '.yaml')}}}\n"
                        "sensor_logs: true\n"
                        "stop: {max_sim_time_s: 40.0, small_interval_s: 20.0}\n")
    data = tmp_path / "data"
    assert main(["collect", str(TINY), "--runs", "1", "--seed", "5", "--out", str(data),
                 "--settings", str(settings), "--no-progress", "--jobs", "1"]) == 0
    run_dir = data / "tiny" / "run_000"
    record = json.loads((run_dir / "run.json").read_text())
    params = slam.load_params(name, config / f"{name}.yaml")
    assert record["slam"] == slam.SlamChoice(name, params).record()
    assert record["config_hashes"][name] == record["slam"]["params_hash"]
    assert record["sensor_logs"][name]
    replay = tmp_path / "replay"
    capsys.readouterr()
    assert main(["slam", "run", str(run_dir / "sensors.bag"), "--out", str(replay)]) == 0
    assert capsys.readouterr().out.startswith(f"{name}:")
    ours = (replay / "slam.tum").read_text().splitlines()
    recorded = (run_dir / "slam_scans.tum").read_text().splitlines()
    body = [line for line in ours if not line.startswith("#")]
    assert body == [line for line in recorded if not line.startswith("#")] and body


def test_a_back_end_module_named_in_the_environment_is_loaded(tmp_path):
    """SLAM_PREDICT_EXTRA_BACKENDS (a .py path here) registers the back-end in a fresh process:
    the CLI's choices and a run."""
    env = dict(os.environ, SLAM_PREDICT_EXTRA_BACKENDS=str(Path(dummy_backend.__file__)),
               PYTHONPATH=os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")]))
    code = ("from slam_predict import slam; from slam_predict.explore import map_sources; "
            "print(slam.available(), map_sources())")
    proc = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert "'dummy'" in proc.stdout and "'perfect'" in proc.stdout
    env[slam.EXTRA_BACKENDS_ENV] = "no_such_backend_module"
    proc = subprocess.run([sys.executable, "-m", "slam_predict.cli.main", "explore", str(TINY),
                           "--out", str(tmp_path / "x")], env=env, capture_output=True, text=True)
    assert proc.returncode == 2
    assert proc.stderr.strip().count("\n") == 0 and "no_such_backend_module" in proc.stderr


def test_unknown_back_end_in_settings_is_a_one_line_error(tmp_path, capsys):
    settings = tmp_path / "collect.yaml"
    settings.write_text(f"extends: {ROOT / 'config' / 'collect.yaml'}\nslam: {{type: gmaping}}\n")
    code = main(["collect", str(TINY), "--runs", "1", "--out", str(tmp_path / "d"),
                 "--settings", str(settings), "--no-progress"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1
    assert "unknown SLAM type 'gmaping'" in err[0] and "did you mean 'gmapping'" in err[0]
