"""How a run's seed becomes the seeds of its parts (one rule for the closed loop and the replay)."""
from __future__ import annotations

import numpy as np


def run_seeds(seed: int) -> list[np.random.SeedSequence]:
    """The seed sequences of the simulator, the explorer and the SLAM back-end of a run."""
    return np.random.SeedSequence(seed).spawn(3)
