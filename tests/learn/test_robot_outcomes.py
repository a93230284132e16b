"""Failed explorations per configuration (learn/robot/outcomes.py) and their warning."""
from __future__ import annotations

import json

import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.learn.robot.outcomes import exploration_outcomes, failure_warning

from . import robot_synthetic as syn


@pytest.fixture()
def campaign(tmp_path):
    """A synthetic campaign (4 buildings × 3 robots × 2 runs) with two runs of the
    shortest-range robot made failures (coverage 0.3)."""
    rng = np.random.default_rng(5)
    worlds = syn.buildings(4, rng)
    robots = [dict(r, range_max=m) for r, m in zip(syn.robot_configs(3, rng), (4.0, 12.0, 28.0),
                                                    strict=True)]
    records = syn.write_campaign(tmp_path, worlds, robots, 2, rng)
    short = [r for r in records if r["design"]["config"] == "c00"][:2]
    for record in short:
        path = record.pop("path")
        record["coverage"] = 0.3
        with open(path, "w") as handle:
            json.dump(record, handle)
    return tmp_path, robots


def test_outcomes_count_runs_and_failures_per_configuration(campaign):
    folder, robots = campaign
    outcomes = exploration_outcomes([folder], 0.5)
    assert outcomes["min_coverage"] == 0.5
    assert outcomes["by_config"] == {
        f"c{c:02d}": {"range_m": pytest.approx(r["range_max"]), "runs": 8,
                      "failed": 2 if c == 0 else 0} for c, r in enumerate(robots)}
    assert all(e["failed"] == 0 for e in exploration_outcomes([folder], 0.2)["by_config"]
               .values())


def test_warning_names_the_failures_near_the_robot_s_range(campaign):
    folder, robots = campaign
    outcomes = exploration_outcomes([folder], 0.5)
    short = robots[0]["range_max"]
    line = failure_warning(outcomes, short)
    assert line.startswith(f"2 of 8 training runs with lasers of {short:.3g} m")
    assert "mapped less than 50 % of the floor" in line
    assert failure_warning(outcomes, 4.9) is not None          # 4 m is within 1.25 × 4.9 m
    assert failure_warning(outcomes, 5.1) is None and failure_warning(outcomes, 28.0) is None
    assert failure_warning(None, short) is None


def test_a_record_without_a_laser_is_named(campaign):
    folder, _ = campaign
    path = next(folder.glob("*/run_000/run.json"))
    record = json.loads(path.read_text())
    del record["sensor"]["laser"]
    path.write_text(json.dumps(record))
    with pytest.raises(InputError, match="run_000"):
        exploration_outcomes([folder], 0.5)
