"""config/robots/seed_realistic.yaml is derived from config/robot.yaml and
config/base_local_planner.yaml by tools/gen_seed_robot.py: the committed file is the generated
one, and it follows its sources."""
from __future__ import annotations

import math
import shutil
from pathlib import Path

import yaml

from slam_predict.robot_file import load_robot

ROOT = Path(__file__).resolve().parents[2]


def test_the_committed_seed_robot_is_the_generated_one(load_bench):
    assert load_bench("gen_seed_robot", "tools").main(["--check"]) == 0, (
        "config/robots/seed_realistic.yaml is stale: run python tools/gen_seed_robot.py")


def test_the_seed_robot_follows_its_sources(tmp_path, load_bench):
    config = tmp_path / "config"
    config.mkdir()
    for name in ("robot.yaml", "base_local_planner.yaml"):
        shutil.copy(ROOT / "config" / name, config / name)
    sim = yaml.safe_load((config / "robot.yaml").read_text())
    sim["sim"]["laser"]["fov"] = math.radians(240.0)
    sim["sim"]["odom"]["error"][2] = math.radians(3.0)
    (config / "robot.yaml").write_text(yaml.safe_dump(sim))
    out = tmp_path / "seed.yaml"
    out.write_text(load_bench("gen_seed_robot", "tools").seed_robot_text(config))
    robot = load_robot(out)
    reference = load_robot(ROOT / "config" / "robots" / "seed_realistic.yaml")
    assert robot.to_sensor_config() != reference.to_sensor_config()
    assert "fov: 240.0" in out.read_text() and "odom_error: [0.01, 0.01, 3.0]" in out.read_text()
