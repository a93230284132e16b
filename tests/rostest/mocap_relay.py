#!/usr/bin/env python3
"""Test helper: plays a motion-capture system. Republishes base_pose_ground_truth as
geometry_msgs/PoseStamped on /mocap/pose, in a mocap frame placed at ~frame (x, y, yaw) of the
world, for a marker body mounted at ~marker (x, y, yaw) in base_link:
pose = frame ⊕ truth ⊕ marker."""
import numpy as np
import rospy
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Odometry

from slam_predict.geometry import compose
from slam_predict.ros.conversions.geometry import odometry_from_ros, pose_to_ros


def main():
    rospy.init_node("mocap_relay")
    frame = np.asarray(rospy.get_param("~frame"), float)
    marker = np.asarray(rospy.get_param("~marker"), float)
    pub = rospy.Publisher("/mocap/pose", PoseStamped, queue_size=100)

    def relay(msg):
        out = PoseStamped()
        out.header.stamp = msg.header.stamp
        out.header.frame_id = "mocap"
        out.pose = pose_to_ros(compose(compose(frame, odometry_from_ros(msg).pose), marker))
        pub.publish(out)

    rospy.Subscriber("base_pose_ground_truth", Odometry, relay, queue_size=100)
    rospy.spin()


if __name__ == "__main__":
    main()
