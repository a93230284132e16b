"""World / OccupancyMap ↔ nav_msgs/OccupancyGrid round trips and conventions."""
from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("nav_msgs.msg", reason="ROS message packages (nav_msgs) not installed")

from slam_predict.ros.conversions.map import OccupancyMap, occupancy_from_ros, occupancy_to_ros  # noqa: E402
from slam_predict.ros.world_map_node import WorldMapServer  # noqa: E402
from slam_predict.world.model import World  # noqa: E402


def sample_world(seed: int = 0) -> World:
    rng = np.random.default_rng(seed)
    occ = rng.random((int(rng.integers(3, 30)), int(rng.integers(3, 30)))) < 0.3
    return World(name="w", occupied=occ, resolution=float(rng.uniform(0.01, 0.2)),
                 origin=(float(rng.uniform(-10, 10)), float(rng.uniform(-10, 10))))


@pytest.mark.parametrize("seed", range(8))
def test_world_round_trip(seed):
    world = sample_world(seed)
    msg = occupancy_to_ros(world)
    back = occupancy_from_ros(msg).to_world()
    assert np.array_equal(back.occupied, world.occupied)
    assert back.resolution == pytest.approx(world.resolution, abs=1e-12)
    assert back.origin == pytest.approx(world.origin, abs=1e-9)


def test_grid_with_unknown_round_trip():
    values = np.array([[0, 100, -1], [50, 0, 0]], dtype=np.int8)
    grid = OccupancyMap(values, 0.1, (1.0, 2.0), frame_id="odom")
    back = occupancy_from_ros(occupancy_to_ros(grid))
    assert np.array_equal(back.values, grid.values) and back.values.dtype == np.int8
    assert (back.resolution, back.origin, back.frame_id) == (0.1, (1.0, 2.0), "odom")
    assert back.occupied().tolist() == [[False, True, True], [True, False, False]]
    assert back.occupied(unknown_is_occupied=False).tolist() == [[False, True, False],
                                                                 [True, False, False]]


def test_message_conventions():
    occ = np.zeros((2, 3), bool)
    occ[0, 0] = True              # top-left cell of our bitmap
    world = World(name="w", occupied=occ, resolution=0.5, origin=(10.0, 20.0))
    msg = occupancy_to_ros(world)
    assert msg.header.frame_id == "map"
    assert (msg.info.width, msg.info.height, msg.info.resolution) == (3, 2, 0.5)
    # origin = corner of cell (0, 0) = bottom-left corner of the bitmap
    assert (msg.info.origin.position.x, msg.info.origin.position.y) == (9.25, 19.5)
    assert msg.info.origin.orientation.w == pytest.approx(1.0)
    # OccupancyGrid row 0 is the bottom: our top-left is message index width * 1 + 0
    assert list(msg.data) == [0, 0, 0, 100, 0, 0]
    # the cell whose centre is (x, y) = (9.5, 20.25) is our top-left one
    col = int((9.5 - msg.info.origin.position.x) / msg.info.resolution)
    row = int((20.25 - msg.info.origin.position.y) / msg.info.resolution)
    assert msg.data[row * msg.info.width + col] == 100


def test_bad_grids_are_rejected():
    with pytest.raises(ValueError, match="-1..100"):
        occupancy_to_ros(OccupancyMap(np.array([[101]], dtype=np.int16), 0.1))
    msg = occupancy_to_ros(sample_world())
    msg.data = msg.data[:-1]
    with pytest.raises(ValueError, match="cells"):
        occupancy_from_ros(msg)
    msg = occupancy_to_ros(sample_world())
    msg.info.origin.orientation.z, msg.info.origin.orientation.w = 0.3826834, 0.9238795
    with pytest.raises(ValueError, match="rotated"):
        occupancy_from_ros(msg)


def test_world_map_server_message():
    world = sample_world(3)
    server = WorldMapServer(world, frame_id="floor")
    msg = server.map_message()
    assert msg.header.frame_id == "floor"
    assert sum(1 for v in msg.data if v == 0) == int((~world.occupied).sum())
