#!/usr/bin/env python3
"""Rebuild tiny.world + tiny.png (used by tests/rostest/world_map.test) with the writer.

Two rooms of a 4 m x 3 m box at 0.05 m/px: outer walls 0.1 m, an inner wall at x = 0 with a
0.8 m door, robot at (-1, 0) facing +x. Run: .venv/bin/python tests/data/world_map/make_tiny.py
"""
from pathlib import Path

import numpy as np

from slam_predict.world.model import World
from slam_predict.world.stagefile import write_world


def tiny_world() -> World:
    occupied = np.ones((60, 80), dtype=bool)       # 80 x 60 px = 4 m x 3 m
    occupied[2:58, 2:78] = False                   # 0.1 m outer walls
    occupied[2:58, 39:41] = True                   # inner wall at x = 0 (0.1 m thick)
    occupied[22:38, 39:41] = False                 # 0.8 m door
    return World(name="tiny", occupied=occupied, resolution=0.05,
                 start_pose=np.array([-1.0, 0.0, 0.0]),
                 provenance={"source": "tests/data/world_map/make_tiny.py"})


if __name__ == "__main__":
    write_world(tiny_world(), Path(__file__).with_name("tiny.world"))
