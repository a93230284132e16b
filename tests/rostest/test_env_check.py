#!/usr/bin/env python3
"""rostest: the env_check node (started by roslaunch like rosrun) imports the PyPI stack."""
import unittest

import rospy
import rostest
from std_msgs.msg import String


class EnvCheckTest(unittest.TestCase):
    def test_node_sees_pypi_packages(self):
        msg = rospy.wait_for_message("/env_check/report", String, timeout=30.0)
        fields = dict(item.split("=", 1) for item in msg.data.split())
        for name in ("numpy", "numba", "sklearn"):
            self.assertIn(name, fields)
            self.assertRegex(fields[name], r"^\d+\.\d+")
        self.assertIn(".venv", fields["python"])


if __name__ == "__main__":
    rospy.init_node("test_env_check")
    rostest.rosrun("slam_predict", "test_env_check", EnvCheckTest)
