"""Shared fixtures: the project root, the shipped worlds and ../shared/data (skip when absent)."""
from __future__ import annotations

import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("SLAM_PREDICT_SHARED", ROOT.parent / "shared"))
SHARED_DATA = SHARED / "data"


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: full end-to-end check; CI runs a short version")


@pytest.fixture(scope="session")
def root() -> Path:
    """The repository root."""
    return ROOT


@pytest.fixture(scope="session")
def shared_data() -> Path:
    """../shared/data, or skip the test with a clear message when it is absent."""
    if not SHARED_DATA.is_dir():
        pytest.skip(f"real data not found at {SHARED_DATA} (set SLAM_PREDICT_SHARED)")
    return SHARED_DATA


@pytest.fixture(scope="session")
def shared_dir() -> Path:
    """../shared (specs, baselines, tools), or skip when absent."""
    if not SHARED.is_dir():
        pytest.skip(f"../shared not found at {SHARED} (set SLAM_PREDICT_SHARED)")
    return SHARED


@pytest.fixture
def read_only_folder(tmp_path) -> Path:
    """An empty folder this process may not write into (skips when it still can, as root)."""
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        if os.access(locked, os.W_OK):
            pytest.skip("this user can write into read-only folders (root)")
        yield locked
    finally:
        locked.chmod(0o700)


@pytest.fixture(scope="session")
def run_record_keys() -> frozenset:
    """run.json's top-level keys as collect.record.build_record writes them (both paths)."""
    return frozenset({
        "world", "world_file", "run_index", "seed", "code_version", "config_hashes",
        "settings_file", "odometry_model", "ranger_model", "odometry_error", "stop_reason",
        "explorer_end",
        "sim_duration_s", "wall_time_s", "distance_m", "rotation_rad", "coverage", "stalls",
        "free_area_m2", "snapshots", "metric", "timing", "sensor", "slam", "stuck",
        "coverage_swept"})


@pytest.fixture(scope="session")
def robot_models_dir(tmp_path_factory) -> Path:
    """A models/ folder holding ``own-robots``: a robot-aware model (elasticnet and gradient
    boosting) trained on the synthetic campaign of tests/learn/robot_synthetic.py, with this
    installation's feature configuration (so ``predict --robot`` runs on real plans; its
    numbers mean nothing there), design bounds and GMapping maxUrange 30 m."""
    from learn import robot_synthetic as syn

    folder = tmp_path_factory.mktemp("robot_models")
    syn.train_model(folder)
    return folder / "models"


@pytest.fixture(scope="session")
def load_bench(root):
    """A loader of bench/ scripts by stem (bench/ is not a package): load_bench("bench_x");
    load_bench("gen_x", "tools") loads a script of another folder."""
    import importlib.util

    def load(stem: str, folder: str = "bench"):
        spec = importlib.util.spec_from_file_location(stem, root / folder / f"{stem}.py")
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        return module

    return load
