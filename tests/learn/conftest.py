"""A small synthetic dataset and a model folder trained on it (fast: a few seconds)."""
from __future__ import annotations

import numpy as np
import pytest

from slam_predict.config import from_dict
from slam_predict.learn import dataset as ds
from slam_predict.learn.config import LearningConfig
from slam_predict.learn.results import run_evaluation
from slam_predict.learn.train import train_store


def synthetic_dataset(n: int = 30, seed: int = 0, version: str = "test-v1") -> ds.Dataset:
    """Targets linear in feature 'length' (m) plus noise; 'noise' is irrelevant."""
    rng = np.random.default_rng(seed)
    length = rng.uniform(50, 1500, n)
    junk = rng.normal(size=n)
    rows = []
    for i in range(n):
        targets = {"trans_mean": 1e-3 * length[i] + 0.05 * rng.normal() + 0.1,
                   "trans_std": 1e-4 * length[i] + 0.005 * rng.normal() + 0.02,
                   "rot_mean": 2e-5 * length[i] + 0.001 * rng.normal() + 0.01,
                   "rot_std": 1e-6 * length[i] + 0.0005 * rng.random() + 0.002}
        rows.append(ds.ErrorRow(f"w{i:02d}", targets, runs=5, setting="realistic",
                                slam_config_hash="abc123"))
    features = {f"w{i:02d}": {"length": float(length[i]), "noise": float(junk[i])}
                for i in range(n)}
    return ds.join(rows, features, version)


def tiny_config() -> LearningConfig:
    return from_dict(LearningConfig, {"models": ["single", "elasticnet"],
                                      "elasticnet": {"alphas": [0.01, 0.1, 1.0],
                                                     "l1_ratios": [0.5, 1.0]},
                                      "conformal": {"cv": 3},
                                      "evaluation": {"n_splits": 3}})


@pytest.fixture(scope="session")
def tiny_models(tmp_path_factory):
    """models/ folder holding 'tiny-realistic' trained on the synthetic dataset."""
    folder = tmp_path_factory.mktemp("models")
    data = synthetic_dataset()
    config = tiny_config()
    outcome = run_evaluation(data, config)
    train_store(data, config, outcome, "tiny-realistic", folder, "synthetic test model",
                feature_config={"some": "config"})
    return folder
