"""A stand-in episode for batch tests: deterministic pseudo-results from the seed, written
atomically like the real episode. ``FAKE_EPISODE_SLEEP`` (s) slows it down for kill tests; like
the real episode loop it checks the stop flag every 10 ms step; ``FAKE_EPISODE_SIGNAL_AT`` and
``FAKE_EPISODE_SIGNAL_PARENT_AT`` send a stop signal from inside a run (signal tests)."""
import json
import os
import signal
import time

import numpy as np

from slam_predict.atomic import atomic_dir
from slam_predict.collect import interrupt


def run_episode(spec):
    rng = np.random.default_rng(spec.seed)
    record = {
        "world": spec.world, "run_index": spec.index, "seed": spec.seed,
        "metric": {"trans_mean": float(rng.uniform(0.1, 0.3)),
                   "rot_mean": float(rng.uniform(0.01, 0.02)),
                   "trans_sqr_mean": float(rng.uniform(0.01, 0.09)),
                   "rot_sqr_mean": float(rng.uniform(1e-4, 4e-4))},
        "distance_m": float(rng.uniform(50, 60)), "rotation_rad": float(rng.uniform(20, 30)),
        "coverage": 0.97, "sim_duration_s": 1200.0, "wall_time_s": time.time(),
    }
    with atomic_dir(spec.out_dir) as tmp:
        (tmp / "trajectory.txt").write_text("x" * 1000)
        _signal_if_asked(spec.index)
        _sleep_checking(float(os.environ.get("FAKE_EPISODE_SLEEP", "0")))
        (tmp / "run.json").write_text(json.dumps(record))
    return record


def _signal_if_asked(index):
    """``FAKE_EPISODE_SIGNAL_AT=i``: run i sends SIGINT to its own process;
    ``FAKE_EPISODE_SIGNAL_PARENT_AT=i``: run i (in a worker) sends SIGTERM to the batch process."""
    if os.environ.get("FAKE_EPISODE_SIGNAL_AT") == str(index):
        os.kill(os.getpid(), signal.SIGINT)
    if os.environ.get("FAKE_EPISODE_SIGNAL_PARENT_AT") == str(index):
        os.kill(os.getppid(), signal.SIGTERM)


def _sleep_checking(seconds):
    """Sleep ``seconds`` in 10 ms steps, checking the stop flag at each (the control step)."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        interrupt.check()
        time.sleep(0.01)
