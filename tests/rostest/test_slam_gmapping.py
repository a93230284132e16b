#!/usr/bin/env python3
"""rostest: slam_gmapping (or sync_slam_toolbox_node, slam_toolbox_sync.test) on stage_sim
publishes a latched, growing map, map -> odom and answers dynamic_map; map_metadata matches the
map."""
import threading
import unittest

import numpy as np
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import Twist
from nav_msgs.msg import MapMetaData, OccupancyGrid
from nav_msgs.srv import GetMap

from slam_predict.ros.conversions.geometry import transform_from_ros
from slam_predict.ros.conversions.slam import grid_from_ros


class Latest:
    def __init__(self, topic, kind):
        self.msg, self.count = None, 0
        self.lock = threading.Lock()
        rospy.Subscriber(topic, kind, self.on_message, queue_size=2)

    def on_message(self, msg):
        with self.lock:
            self.msg, self.count = msg, self.count + 1


def drive(pub, seconds, forward, turn):
    """Command the robot for ``seconds`` of sim time at 10 Hz."""
    end = rospy.Time.now() + rospy.Duration(seconds)
    cmd = Twist()
    cmd.linear.x, cmd.angular.z = forward, turn
    while not rospy.is_shutdown() and rospy.Time.now() < end:
        pub.publish(cmd)
        rospy.sleep(0.1)
    pub.publish(Twist())


def wait_for(predicate, timeout):
    deadline = rospy.get_rostime() + rospy.Duration(timeout)
    while not rospy.is_shutdown() and not predicate():
        if rospy.get_rostime() > deadline:
            return False
        rospy.sleep(0.1)
    return True


def shape_of(maps):
    with maps.lock:
        return maps.count, (maps.msg.info.width, maps.msg.info.height)


def wait_until_settled(maps, timeout):
    """Wait until two successive map messages have the same size: the robot has stopped and the
    back-end has processed the scans it had queued, so the map no longer grows."""
    deadline = rospy.get_rostime() + rospy.Duration(timeout)
    count, size = shape_of(maps)
    while not rospy.is_shutdown() and rospy.get_rostime() <= deadline:
        if not wait_for(lambda seen=count: maps.count > seen, timeout):
            return False
        count, newer = shape_of(maps)
        if newer == size:
            return True
        size = newer
    return False


class SlamGMappingTest(unittest.TestCase):
    def test_map_grows_and_tf_is_broadcast(self):
        maps = Latest("map", OccupancyGrid)
        meta = Latest("map_metadata", MapMetaData)
        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        cmd = rospy.Publisher("cmd_vel", Twist, queue_size=1)
        self.assertTrue(wait_for(lambda: maps.msg is not None, 60.0), "no map published")
        first = grid_from_ros(maps.msg)
        self.assertEqual(maps.msg.header.frame_id, "map")
        known0 = int((first.data >= 0).sum())
        self.assertGreater(known0, 100)
        count = maps.count            # a fast back-end publishes while the robot drives
        drive(cmd, 8.0, 0.0, 0.6)     # turn on the spot: the hidden half of the room appears
        drive(cmd, 6.0, 0.3, 0.0)
        self.assertTrue(wait_for(lambda: maps.count > count, 30.0), "map not updated")
        self.assertTrue(wait_until_settled(maps, 30.0), "map still growing 30 s after the stop")
        with maps.lock:
            last = grid_from_ros(maps.msg)
        # 270° laser: most is seen at once
        self.assertGreater(int((last.data >= 0).sum()), known0 * 1.05)
        self.assertGreater(int((last.data == 100).sum()), 200)
        with meta.lock:
            info = meta.msg
        self.assertEqual((info.width, info.height), (last.width, last.height))
        tf = transform_from_ros(buffer.lookup_transform("map", "odom", rospy.Time(0),
                                                        rospy.Duration(5.0)))
        self.assertLess(float(np.hypot(*tf.pose[:2])), 1.0)
        rospy.wait_for_service("dynamic_map", timeout=10.0)
        served = grid_from_ros(rospy.ServiceProxy("dynamic_map", GetMap)().map)
        self.assertEqual(served.data.shape, last.data.shape)


if __name__ == "__main__":
    rospy.init_node("test_slam_gmapping")
    rostest.rosrun("slam_predict", "test_slam_gmapping", SlamGMappingTest)
