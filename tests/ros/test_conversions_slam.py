"""SLAM grids ↔ nav_msgs/OccupancyGrid: byte-exact round trips through the wire format."""
from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("nav_msgs.msg", reason="ROS message packages (nav_msgs) not installed")

from nav_msgs.msg import OccupancyGrid as RosGrid  # noqa: E402
from nav_msgs.srv import GetMapResponse  # noqa: E402
from ros_wire import wire  # noqa: E402

from slam_predict.ros.conversions.slam import (  # noqa: E402
    get_map_response,
    grid_from_ros,
    grid_to_ros,
    metadata_to_ros,
)
from slam_predict.slam import OccupancyGrid  # noqa: E402


def sample_grid(seed=0):
    rng = np.random.default_rng(seed)
    data = rng.choice(np.array([-1, 0, 100], dtype=np.int8), size=(37, 53))
    return OccupancyGrid(data, 0.05, (-12.5, 3.25))


@pytest.mark.parametrize("seed", range(3))
def test_grid_round_trip_through_the_wire(seed):
    grid = sample_grid(seed)
    msg = grid_to_ros(grid, "map", 12.5)
    plain = wire(msg, RosGrid)                         # a normal subscriber's view
    assert plain.header.frame_id == "map" and plain.header.stamp.to_sec() == 12.5
    assert (plain.info.width, plain.info.height) == (53, 37)
    assert plain.info.resolution == pytest.approx(0.05)
    assert list(plain.data[:53]) == grid.data[0].tolist()  # row 0 = smallest y first
    back = grid_from_ros(plain)
    assert np.array_equal(back.data, grid.data) and back.origin == grid.origin
    assert np.array_equal(grid_from_ros(msg).data, grid.data)


def test_metadata_and_get_map_response():
    grid = sample_grid()
    info = metadata_to_ros(grid, 3.0)
    assert (info.width, info.height, info.origin.position.x) == (53, 37, -12.5)
    assert info.origin.orientation.w == 1.0
    response = wire(get_map_response(grid_to_ros(grid)), GetMapResponse)
    assert np.array_equal(grid_from_ros(response.map).data, grid.data)


def test_bad_messages_are_refused():
    msg = wire(grid_to_ros(sample_grid()), RosGrid)
    msg.info.width = 10
    with pytest.raises(ValueError, match="cells"):
        grid_from_ros(msg)
    msg = wire(grid_to_ros(sample_grid()), RosGrid)
    msg.info.origin.orientation.z, msg.info.origin.orientation.w = 0.3826834, 0.9238795
    with pytest.raises(ValueError, match="rotated"):
        grid_from_ros(msg)
