"""Round trips of the navigation conversions (costmaps, plans, goals, frontier markers)."""
from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("move_base_msgs.msg", reason="ROS message packages not installed")

from geometry_msgs.msg import Quaternion  # noqa: E402

from slam_predict.explore.frontiers import Frontier  # noqa: E402
from slam_predict.nav.costmap import Costmap  # noqa: E402
from slam_predict.ros.conversions import nav as conv  # noqa: E402


def test_costmap_translation_table_and_round_trip():
    costs = np.arange(256, dtype=np.uint8).reshape(16, 16)
    values = conv.costmap_values(costs)
    assert values[0, 0] == 0 and values.flat[253] == 99 and values.flat[254] == 100
    assert values.flat[255] == -1 and values.flat[252] == 1 + 97 * 251 // 251
    assert np.all(np.diff(values.flat[:254].astype(int)) >= 0)
    cm = Costmap(costs, (1.5, -2.0), 0.05)
    msg = conv.costmap_to_ros(cm, "odom", 3.0)
    assert msg.header.frame_id == "odom" and msg.info.width == 16
    back = conv.costmap_from_ros(msg)
    assert back.origin == (1.5, -2.0) and back.resolution == 0.05
    np.testing.assert_array_equal(conv.costmap_values(back.costs), values)
    for special in (0, 253, 254, 255):
        assert back.costs.flat[special] == special


@pytest.mark.parametrize("seed", range(4))
def test_plan_round_trip(seed):
    rng = np.random.default_rng(seed)
    poses = np.column_stack([rng.normal(size=(7, 2)), rng.uniform(-3, 3, 7)])
    back = conv.plan_from_ros(conv.plan_to_ros(poses, "map", 1.0))
    np.testing.assert_allclose(back, poses, atol=1e-9)
    assert conv.plan_from_ros(conv.plan_to_ros(np.empty((0, 3)), "map")).shape == (0, 3)


def test_goal_round_trip_and_quaternion_check():
    target = (1.0, -2.5, 2.0)
    goal = conv.goal_to_ros(target, "map", 5.0)
    (pose, frame) = conv.goal_from_ros(goal)
    np.testing.assert_allclose(pose, target, atol=1e-12)
    assert frame == "map"
    goal.target_pose.pose.orientation = Quaternion(0.0, 0.0, 0.0, 0.0)
    assert conv.goal_from_ros(goal) is None
    goal.target_pose.pose.orientation = Quaternion(0.7071, 0.0, 0.0, 0.7071)   # roll 90°
    assert conv.goal_from_ros(goal) is None
    goal.target_pose.pose.orientation = Quaternion(0.0, 0.0, float("nan"), 1.0)
    assert conv.goal_from_ros(goal) is None
    goal.target_pose.pose.orientation = Quaternion(0.0, 0.0, math.sin(0.3), math.cos(0.3))
    assert conv.goal_from_ros(goal)[0][2] == pytest.approx(0.6)


def test_frontier_markers_round_trip():
    rng = np.random.default_rng(1)
    frontiers = []
    for _ in range(3):
        cells = rng.normal(size=(5, 2))
        frontiers.append(Frontier(cells, 5, cells.mean(axis=0), cells[2], 1.0))
    msg = conv.frontiers_to_ros(frontiers, "map", 2.0, blacklisted=[False, True, False])
    assert msg.markers[0].action == msg.markers[0].DELETEALL
    back = conv.frontiers_from_ros(msg)
    assert len(back) == 3
    for (cells, goal), f in zip(back, frontiers, strict=False):
        np.testing.assert_allclose(cells, f.cells)
        np.testing.assert_allclose(goal, f.goal)
    assert msg.markers[3].color.r == 1.0 and msg.markers[1].color.b == 1.0


def test_polygon_round_trip_places_the_footprint_at_the_pose():
    square = np.array([[-0.2, -0.2], [0.2, -0.2], [0.2, 0.2], [-0.2, 0.2]])
    msg = conv.polygon_to_ros(square, (1.0, 2.0, math.pi / 2), "odom", 3.5)
    assert msg.header.frame_id == "odom" and msg.header.stamp.to_sec() == pytest.approx(3.5)
    back = conv.polygon_from_ros(msg)
    # reference: rotate each vertex by 90 deg by hand ((x, y) -> (-y, x)), then translate
    expected = np.array([[1.0 - y, 2.0 + x] for x, y in square])
    np.testing.assert_allclose(back, expected, atol=1e-6)   # Point32: float32
