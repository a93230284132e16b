"""start_node: a node's parameters, or one fatal line on bad ones (no ROS master needed)."""
from __future__ import annotations

from slam_predict.errors import InputError
from slam_predict.ros.node_start import start_node


class FakeRospy:
    def __init__(self):
        self.names = []
        self.fatal = []

    def init_node(self, name, argv=None):
        self.names.append((name, argv))

    def logfatal(self, text):
        self.fatal.append(text)


def test_returns_what_read_returns():
    rospy = FakeRospy()
    assert start_node(rospy, "slam_toolbox", "async_slam_toolbox_node",
                      lambda module: ("params", module), ["x"]) == ("params", rospy)
    assert rospy.names == [("slam_toolbox", ["x"])]
    assert rospy.fatal == []


def test_bad_parameters_give_one_fatal_line_and_none():
    def read(_module):
        raise InputError("unknown key 'max_vel'", "/explore parameters")

    rospy = FakeRospy()
    assert start_node(rospy, "explore", "explore", read) is None
    assert len(rospy.fatal) == 1
    assert rospy.fatal[0].startswith("explore: ")
    assert "unknown key 'max_vel'" in rospy.fatal[0]
