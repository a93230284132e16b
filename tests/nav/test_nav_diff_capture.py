"""bench/nav_diff's capture of an episode (tiny world, 10 s), no upstream needed: the captured
cycles replayed through our planner give the captured commands, and the captured navfn
requests and our plans read back."""
import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
HERE = ROOT / "bench" / "nav_diff"
SETTINGS = ROOT / "config" / "fidelity" / "seed_study_refit_escape.yaml"


def _module(name):
    if str(HERE) not in sys.path:
        sys.path.insert(0, str(HERE))
    spec = importlib.util.spec_from_file_location(name, HERE / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def case(tmp_path_factory):
    folder = tmp_path_factory.mktemp("navdiff") / "tiny"
    counts = _module("capture").capture(ROOT / "worlds" / "tiny.world", 5, SETTINGS, 10.0,
                                        folder)
    return folder, counts


def test_replay_of_the_capture_repeats_our_commands(case):
    folder, counts = case
    from slam_predict.nav.config import TrajectoryPlannerConfig

    assert counts["cycles"] > 20 and counts["maps"] >= 1
    ours = dict(np.load(folder / "ours.npz"))
    assert len(ours["xv"]) == counts["cycles"]
    lines = dict(line.split(" ", 1) for line in (folder / "params.txt").read_text().splitlines())
    cfg = TrajectoryPlannerConfig(**{
        k: type(getattr(TrajectoryPlannerConfig(), k))(float(v)) for k, v in lines.items()
        if k in TrajectoryPlannerConfig.__dataclass_fields__})
    footprint = np.array(lines["footprint"].split()[1:], float).reshape(-1, 2)
    again = _module("replay").replay(folder, cfg, footprint, float(lines["sim_period"]))
    assert np.array_equal(again["xv"], ours["xv"])
    assert np.array_equal(again["thetav"], ours["thetav"])
    assert np.array_equal(again["cost"], ours["cost"])


def test_plans_read_back(case):
    folder, counts = case
    plans = _module("plans")
    ours = dict(np.load(folder / "ours_plans.npz"))
    assert counts["plans"] == len(ours["found"]) >= 1
    widths = plans.request_widths(folder / "plans.bin")
    assert len(widths) == counts["plans"] and (widths > 0).all()
    assert ours["offsets"][-1] == len(ours["poses"])
    (folder / "navfn.txt").write_text("navfn_diff_driver 1\n0 2 0.5 0.5 1.5 1.5\n1 0\n")
    real = plans.read_navfn_output(folder / "navfn.txt")
    assert real[0].tolist() == [[0.5, 0.5], [1.5, 1.5]] and real[1].shape == (0, 2)
