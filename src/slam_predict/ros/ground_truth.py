"""Ground-truth sources of the orchestrator: the simulator, a motion-capture system, or tf.

``source`` (config/orchestrator.yaml, section ``ground_truth``):

* ``odometry`` — a ``nav_msgs/Odometry`` topic; default ``base_pose_ground_truth`` (stageros and
  stage_sim publish the true world pose there); also any external odometry-typed tracker;
* ``pose`` — a ``geometry_msgs/PoseStamped`` topic, e.g. mocap_optitrack's
  ``/<rigid_body>/pose`` or vrpn_client_ros' ``/vrpn_client_node/<body>/pose``;
* ``pose_cov`` — a ``geometry_msgs/PoseWithCovarianceStamped`` topic;
* ``tf`` — the tf frame ``frame`` (the tracked body, e.g. ``robot_mocap``) in ``fixed_frame``
  (e.g. ``world``/``mocap``), looked up at each sample time.

Poses are projected on the plane (x, y, yaw). ``offset`` is base_link's pose (x m, y m, yaw rad)
in the tracked body's frame — the markers' rigid body is rarely centred on base_link, and a
constant body-frame offset changes relative errors — so the recorded ground truth is
``body ⊕ offset``. For topic sources a sample at time t takes the message whose stamp is nearest
to t, once a message stamped ≥ t has arrived; none within ``tolerance`` s drops the sample.
"""
from __future__ import annotations

import bisect
import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from slam_predict.config import POSITIVE, Range
from slam_predict.errors import InputError, did_you_mean
from slam_predict.geometry import compose
from slam_predict.ros.orchestrator import Unavailable

SOURCES = ("odometry", "pose", "pose_cov", "tf")


@dataclass
class GroundTruthConfig:
    """Where the orchestrator reads ground truth (module docstring)."""

    source: str = "odometry"
    topic: str = "base_pose_ground_truth"
    frame: str = ""
    fixed_frame: str = "world"
    offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    tolerance: float = 0.05
    keep_s: float = 60.0
    RANGES: ClassVar[dict[str, Range]] = {"tolerance": POSITIVE, "keep_s": POSITIVE}

    def __post_init__(self) -> None:
        if self.source not in SOURCES:
            raise ValueError(f"ground_truth.source '{self.source}' is not one of "
                             f"{', '.join(SOURCES)}" + did_you_mean(self.source, SOURCES))
        if self.source == "tf" and not self.frame:
            raise ValueError("ground_truth.source 'tf' needs ground_truth.frame (the tracked body)")
        if self.tolerance <= 0:
            raise ValueError("ground_truth.tolerance must be > 0 s")


class PoseHistory:
    """Time-stamped planar poses of a topic source, searchable by time (pure, no ROS)."""

    def __init__(self, tolerance: float, keep_s: float = 60.0):
        self.tolerance = float(tolerance)
        self.keep_s = float(keep_s)
        self.stamps: list[float] = []
        self.poses: list[np.ndarray] = []

    def add(self, t: float, pose) -> None:
        """Insert a pose stamped ``t`` s (out-of-order stamps are sorted in)."""
        i = bisect.bisect_right(self.stamps, t)
        self.stamps.insert(i, float(t))
        self.poses.insert(i, np.asarray(pose, float))
        cut = bisect.bisect_left(self.stamps, self.stamps[-1] - self.keep_s)
        if cut > 0:
            del self.stamps[:cut], self.poses[:cut]

    def at(self, t: float) -> np.ndarray | None:
        """The pose nearest in time to ``t``; None while no message stamped ≥ t has arrived.

        Raises :class:`Unavailable` when the nearest one is more than ``tolerance`` s away.
        """
        if not self.stamps or self.stamps[-1] < t:
            return None
        i = bisect.bisect_left(self.stamps, t)
        candidates = [j for j in (i - 1, i) if 0 <= j < len(self.stamps)]
        j = min(candidates, key=lambda k: abs(self.stamps[k] - t))
        if abs(self.stamps[j] - t) > self.tolerance:
            raise Unavailable(f"no ground truth within {self.tolerance} s of {t:.3f} s")
        return self.poses[j]


class GroundTruthSource:
    """A configured source; ``at(t)`` → world pose of base_link, None (not yet) or Unavailable.

    Args:
        config: the source settings.
        rospy_module: ``rospy`` (subscriptions); tf_pose: ``(parent, child, t) -> pose or None``
            for the ``tf`` source.
    """

    def __init__(self, config: GroundTruthConfig, rospy_module=None,
                 tf_pose: Callable[[str, str, float], np.ndarray | None] | None = None):
        self.config = config
        self.history = PoseHistory(config.tolerance, config.keep_s)
        self.tf_pose = tf_pose
        self.offset = np.asarray(config.offset, float)
        self.messages = 0
        self._lock = threading.Lock()
        if config.source != "tf":
            kind, self._extract = _message_kind(config.source)
            if rospy_module is not None:
                rospy_module.Subscriber(config.topic, kind, self.on_message, queue_size=1000)

    def on_message(self, msg) -> None:
        """Topic callback: store the message's planar pose at its stamp."""
        from slam_predict.ros.conversions.geometry import pose_from_ros, time_from_ros

        pose = pose_from_ros(self._extract(msg))
        with self._lock:
            self.messages += 1
            self.history.add(time_from_ros(msg.header.stamp), pose)

    def at(self, t: float) -> np.ndarray | None:
        """Ground truth of base_link at ``t`` (s) in the source's fixed frame."""
        if self.config.source == "tf":
            body = self.tf_pose(self.config.fixed_frame, self.config.frame, t)
        else:
            with self._lock:
                body = self.history.at(t)
        if body is None:
            return None
        return compose(body, self.offset) if self.offset.any() else np.array(body, float)

    def describe(self) -> dict:
        """JSON-ready description for run.json."""
        c = self.config
        where = {"frame": c.frame, "fixed_frame": c.fixed_frame} if c.source == "tf" else {
            "topic": c.topic}
        return {"source": c.source, **where, "offset": list(c.offset), "tolerance": c.tolerance}


def _message_kind(source: str):
    """(message class, msg → geometry_msgs/Pose) of a topic source."""
    if source == "odometry":
        from nav_msgs.msg import Odometry
        return Odometry, lambda m: m.pose.pose
    if source == "pose":
        from geometry_msgs.msg import PoseStamped
        return PoseStamped, lambda m: m.pose
    if source == "pose_cov":
        from geometry_msgs.msg import PoseWithCovarianceStamped
        return PoseWithCovarianceStamped, lambda m: m.pose.pose
    raise InputError(f"ground-truth source '{source}' has no topic")
