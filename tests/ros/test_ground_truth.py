"""Ground-truth sources: time matching of topic messages, body offset, tf source, config."""
from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("geometry_msgs.msg", reason="ROS 1 python messages not installed")

from geometry_msgs.msg import PoseStamped, PoseWithCovarianceStamped  # noqa: E402

from slam_predict.config import from_dict  # noqa: E402
from slam_predict.errors import InputError  # noqa: E402
from slam_predict.geometry import compose  # noqa: E402
from slam_predict.ros.conversions.geometry import odometry_to_ros, pose_to_ros, time_to_ros  # noqa: E402
from slam_predict.ros.ground_truth import GroundTruthConfig, GroundTruthSource, PoseHistory  # noqa: E402
from slam_predict.ros.orchestrator import Unavailable  # noqa: E402


def test_history_nearest_in_time_waits_and_reports_gaps():
    h = PoseHistory(tolerance=0.02)
    for t in (0.10, 0.2, 0.3, 0.9):
        h.add(t, [t, 0.0, 0.0])
    assert h.at(0.205)[0] == pytest.approx(0.2)
    assert h.at(0.29)[0] == pytest.approx(0.3)
    assert h.at(0.1)[0] == pytest.approx(0.1)
    assert h.at(0.95) is None                   # nothing stamped >= t yet
    with pytest.raises(Unavailable):
        h.at(0.5)                               # nearest is 0.2 s away
    h.add(0.5, [0.5, 0.0, 0.0])                 # late, out-of-order message is sorted in
    assert h.at(0.5)[0] == pytest.approx(0.5)


def test_history_prunes_old_messages():
    h = PoseHistory(tolerance=0.05, keep_s=1.0)
    for k in range(50):
        h.add(k * 0.1, [k, 0, 0])
    assert h.stamps[0] >= 3.9 - 1e-9 and len(h.stamps) <= 11
    with pytest.raises(Unavailable):
        h.at(1.0)


def pose_stamped(t, pose):
    msg = PoseStamped()
    msg.header.stamp = time_to_ros(t)
    msg.pose = pose_to_ros(pose)
    return msg


def test_pose_topic_source_with_offset():
    offset = (0.1, -0.05, 0.2)   # base_link in the marker body's frame
    src = GroundTruthSource(GroundTruthConfig(source="pose", topic="/mocap/pose", offset=offset))
    body = np.array([1.0, 2.0, 0.5])
    src.on_message(pose_stamped(3.0, body))
    np.testing.assert_allclose(src.at(3.0), compose(body, offset), atol=1e-12)
    assert src.at(3.1) is None and src.messages == 1
    assert src.describe()["source"] == "pose" and src.describe()["topic"] == "/mocap/pose"


def test_odometry_and_pose_cov_sources_read_the_pose():
    src = GroundTruthSource(GroundTruthConfig())
    src.on_message(odometry_to_ros((1.0, -1.0, 0.3), (0.0, 0.0, 0.0), 0.1, "odom", "base"))
    np.testing.assert_allclose(src.at(0.1), [1.0, -1.0, 0.3], atol=1e-12)
    cov = GroundTruthSource(GroundTruthConfig(source="pose_cov", topic="p"))
    msg = PoseWithCovarianceStamped()
    msg.header.stamp = time_to_ros(2.0)
    msg.pose.pose = pose_to_ros((4.0, 5.0, -1.0))
    cov.on_message(msg)
    np.testing.assert_allclose(cov.at(2.0), [4.0, 5.0, -1.0], atol=1e-12)


class FakeRospy:
    def __init__(self):
        self.subscriptions = []

    def Subscriber(self, topic, kind, callback, queue_size=None):  # noqa: N802 (rospy API)
        self.subscriptions.append((topic, kind, callback))


def test_topic_sources_subscribe_the_right_type():
    rp = FakeRospy()
    GroundTruthSource(GroundTruthConfig(source="pose", topic="/robot/pose"), rp)
    assert rp.subscriptions[0][:2] == ("/robot/pose", PoseStamped)
    rp = FakeRospy()
    GroundTruthSource(GroundTruthConfig(source="tf", frame="robot_mocap"), rp)
    assert rp.subscriptions == []


def test_tf_source_looks_up_the_body_frame():
    calls = []

    def tf_pose(parent, child, t):
        calls.append((parent, child, t))
        return None if t > 5 else np.array([t, 0.0, 0.0])

    src = GroundTruthSource(GroundTruthConfig(source="tf", frame="robot_mocap",
                                              fixed_frame="mocap", offset=(0.0, 0.0, 0.1)),
                            tf_pose=tf_pose)
    np.testing.assert_allclose(src.at(2.0), [2.0, 0.0, 0.1])
    assert src.at(6.0) is None and calls[0] == ("mocap", "robot_mocap", 2.0)


def test_config_rejects_bad_sources():
    with pytest.raises(InputError, match="did you mean 'pose'"):
        from_dict(GroundTruthConfig, {"source": "poses"}, "orchestrator.yaml")
    with pytest.raises(InputError, match="needs ground_truth.frame"):
        from_dict(GroundTruthConfig, {"source": "tf"}, "orchestrator.yaml")
    with pytest.raises(InputError, match="unknown config key 'topik'"):
        from_dict(GroundTruthConfig, {"topik": "x"}, "orchestrator.yaml")
