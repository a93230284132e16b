#!/usr/bin/env python3
"""rostest: world_map_server publishes the world's grid, latched, with the right geometry.

With ``~expect_failure`` the node was given a missing world: no map may ever be advertised.
Expected figures come from ``~width``/``~height``/``~resolution``/``~free_cells`` when given,
and are cross-checked against the library's own loading of ``~world``.
"""
import time
import unittest

import rospy
import rostest
from nav_msgs.msg import MapMetaData, OccupancyGrid


class WorldMapTest(unittest.TestCase):
    def expected(self):
        from slam_predict.world.load import load_plan

        world = load_plan(rospy.get_param("~world"))
        rows, cols = world.shape
        want = {"width": cols, "height": rows, "resolution": world.resolution,
                "free_cells": int((~world.occupied).sum())}
        for key, value in want.items():   # the fixed figures of the .test file, if any
            if rospy.has_param("~" + key):
                self.assertAlmostEqual(rospy.get_param("~" + key), value, places=9)
        return want

    def test_map_matches_world(self):
        if rospy.get_param("~expect_failure", False):
            self.skipTest("failure scenario")
        want = self.expected()
        msg = rospy.wait_for_message("/map", OccupancyGrid, timeout=30.0)
        self.assertEqual(msg.header.frame_id, "map")
        self.assertEqual(msg.info.width, want["width"])
        self.assertEqual(msg.info.height, want["height"])
        self.assertAlmostEqual(msg.info.resolution, want["resolution"], places=6)
        self.assertEqual(len(msg.data), msg.info.width * msg.info.height)
        self.assertEqual(sum(1 for v in msg.data if v == 0), want["free_cells"])
        self.assertEqual(set(msg.data), {0, 100})
        # the world is centred on (0, 0): the grid's corner is at -(W/2, H/2)
        res = msg.info.resolution
        self.assertAlmostEqual(msg.info.origin.position.x, -msg.info.width * res / 2)
        self.assertAlmostEqual(msg.info.origin.position.y, -msg.info.height * res / 2)
        # row 0 of the message is the bottom: its first and last rows are outer wall
        width = msg.info.width
        self.assertTrue(all(v == 100 for v in msg.data[:width]))
        self.assertTrue(all(v == 100 for v in msg.data[-width:]))
        meta = rospy.wait_for_message("/map_metadata", MapMetaData, timeout=30.0)
        self.assertEqual((meta.width, meta.height), (msg.info.width, msg.info.height))

    def test_missing_world_publishes_nothing(self):
        if not rospy.get_param("~expect_failure", False):
            self.skipTest("success scenario")
        deadline = time.time() + 8.0
        while time.time() < deadline:
            topics = [name for name, _ in rospy.get_published_topics()]
            self.assertNotIn("/map", topics)
            time.sleep(0.5)
        with self.assertRaises(rospy.ROSException):
            rospy.wait_for_message("/map", OccupancyGrid, timeout=1.0)


if __name__ == "__main__":
    rospy.init_node("test_world_map")
    rostest.rosrun("slam_predict", "test_world_map", WorldMapTest)
