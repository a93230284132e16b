"""Pose topics from ROS bags (rosbags package): PoseStamped, Odometry, /tf chains, errors."""
from __future__ import annotations

import numpy as np
import pytest
from rosbags.rosbag1 import Writer
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from slam_predict.errors import InputError
from slam_predict.formats.rosbag import read_pose_topic, write_pose_bag

STORE = get_typestore(Stores.ROS1_NOETIC)
# The Noetic store of rosbags lacks tf2_msgs; register TFMessage from its definition.
STORE.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms",
                                  "tf2_msgs/msg/TFMessage"))
T = STORE.types


def _header(t, frame):
    sec = int(t)
    return T["std_msgs/msg/Header"](seq=0, stamp=T["builtin_interfaces/msg/Time"](
        sec=sec, nanosec=int(round((t - sec) * 1e9))), frame_id=frame)


def _quat(yaw):
    return T["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=float(np.sin(yaw / 2)),
                                             w=float(np.cos(yaw / 2)))


def _odometry(t, pose):
    pose_msg = T["geometry_msgs/msg/Pose"](
        position=T["geometry_msgs/msg/Point"](x=pose[0], y=pose[1], z=0.0),
        orientation=_quat(pose[2]))
    cov = T["geometry_msgs/msg/PoseWithCovariance"](pose=pose_msg, covariance=np.zeros(36))
    twist = T["geometry_msgs/msg/TwistWithCovariance"](
        twist=T["geometry_msgs/msg/Twist"](
            linear=T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0),
            angular=T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0)),
        covariance=np.zeros(36))
    return T["nav_msgs/msg/Odometry"](header=_header(t, "odom"), child_frame_id="base_link",
                                      pose=cov, twist=twist)


def _tf(t, pose, parent, child):
    tr = T["geometry_msgs/msg/TransformStamped"](
        header=_header(t, parent), child_frame_id=child,
        transform=T["geometry_msgs/msg/Transform"](
            translation=T["geometry_msgs/msg/Vector3"](x=pose[0], y=pose[1], z=0.0),
            rotation=_quat(pose[2])))
    return T["tf2_msgs/msg/TFMessage"](transforms=[tr])


@pytest.fixture
def bag(tmp_path):
    rng = np.random.default_rng(0)
    t = 50.0 + 0.1 * np.arange(20)
    poses = np.column_stack([rng.normal(size=20), rng.normal(size=20), rng.uniform(-3, 3, 20)])
    path = tmp_path / "a.bag"
    with Writer(path) as writer:
        odom = writer.add_connection("/odom", "nav_msgs/msg/Odometry", typestore=STORE)
        tf = writer.add_connection("/tf", "tf2_msgs/msg/TFMessage", typestore=STORE)
        for ti, p in zip(t[::-1], poses[::-1], strict=False):  # written out of order on purpose
            ns = int(round(ti * 1e9))
            writer.write(odom, ns, STORE.serialize_ros1(_odometry(ti, p), odom.msgtype))
            writer.write(tf, ns,
                         STORE.serialize_ros1(_tf(ti, p + 1.0, "odom", "base_link"), tf.msgtype))
            writer.write(tf, ns, STORE.serialize_ros1(_tf(ti, p, "map", "odom"), tf.msgtype))
    return path, t, poses


def test_odometry_topic_sorted_by_stamp(bag):
    path, t, poses = bag
    t2, p2 = read_pose_topic(path, "/odom")
    np.testing.assert_allclose(t2, t, atol=1e-9)
    np.testing.assert_allclose(p2, poses, atol=1e-12)


def test_tf_parent_child(bag):
    path, t, poses = bag
    t2, p2 = read_pose_topic(path, "/tf:odom.base_link")
    np.testing.assert_allclose(p2[:, :2], poses[:, :2] + 1.0, atol=1e-12)
    with pytest.raises(InputError, match="no poses"):
        read_pose_topic(path, "/tf:map.base_link")     # chains are not composed
    with pytest.raises(InputError, match="parent.child"):
        read_pose_topic(path, "/tf:map")


def test_pose_stamped_round_trip(tmp_path):
    t = 1.7e9 + np.array([0.0, 0.1, 0.25])
    poses = np.array([[1.0, 2.0, 0.1], [1.5, 2.5, -3.0], [0.0, 0.0, 3.1]])
    write_pose_bag(tmp_path / "p.bag", {"/gt": (t, poses)})
    t2, p2 = read_pose_topic(tmp_path / "p.bag", "/gt")
    np.testing.assert_allclose(t2, t, atol=1e-6)
    np.testing.assert_allclose(p2, poses, atol=1e-12)


def test_errors(bag, tmp_path):
    path, *_ = bag
    with pytest.raises(InputError, match="did you mean '/odom'"):
        read_pose_topic(path, "/odomm")
    with pytest.raises(InputError, match="supported"):
        read_pose_topic(path, "/tf")
    with pytest.raises(InputError, match="not found"):
        read_pose_topic(tmp_path / "none.bag", "/odom")
