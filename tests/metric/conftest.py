"""Fixtures of the metric tests."""
from __future__ import annotations

import numpy as np
import pytest
from metric_trajgen import perturbed, random_walk


@pytest.fixture
def trajectories():
    """(estimate, reference): a 300-pose random walk and a drifting copy of it."""
    rng = np.random.default_rng(42)
    ref = random_walk(rng, 300)
    return perturbed(rng, ref), ref
