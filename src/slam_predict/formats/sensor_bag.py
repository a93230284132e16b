"""A ROS 1 bag of stage_ros' sensor stream, written step by step (``rosbags`` writer).

Topics, as ``rosbag record`` of the seed study's graph holds them (see
:mod:`.stage_stream`): ``/tf`` (tf2_msgs/TFMessage: odom → base_footprint,
base_footprint → base_link, base_link → base_laser_link, every step), ``/odom`` and
``/base_pose_ground_truth`` (nav_msgs/Odometry, every step), ``/base_scan``
(sensor_msgs/LaserScan, every scan). Each message is recorded at its header stamp. Chunks are
not compressed by default, as ``rosbag record``'s: Debian's rosbag (roslz4) fails on the
rosbags writer's LZ4 chunks ("malformed data to decompress"), although LZ4 makes the bag 2.6
times smaller and rosbags reads it. The bag is written under a temporary name and renamed by
:meth:`SensorBagWriter.close`; :meth:`SensorBagWriter.abort` deletes it.
"""
from __future__ import annotations

import contextlib
import os

import numpy as np

from slam_predict.atomic import atomic_path
from slam_predict.formats.stage_stream import (
    FOOTPRINT_FRAME,
    ODOM_FRAME,
    ODOM_TOPIC,
    SCAN_TOPIC,
    TRUTH_TOPIC,
    LaserDescription,
    StepMessages,
)
from slam_predict.geometry import yaw_to_quaternion

TF_TYPE, TF_DEFINITION = "tf2_msgs/msg/TFMessage", "geometry_msgs/TransformStamped[] transforms"
TOPIC_TYPES = {"/tf": TF_TYPE, ODOM_TOPIC: "nav_msgs/msg/Odometry",
               TRUTH_TOPIC: "nav_msgs/msg/Odometry", SCAN_TOPIC: "sensor_msgs/msg/LaserScan"}


class SensorBagWriter:
    """Streams :class:`~slam_predict.formats.stage_stream.StepMessages` into a bag at ``path``.

    ``truth_frame``: frame_id of the ground-truth odometry (stage_ros: ``odom``, sic);
    ``compression``: ``lz4``, ``bz2`` or ``none``.
    """

    def __init__(self, path: os.PathLike | str, laser: LaserDescription,
                 truth_frame: str = ODOM_FRAME, compression: str = "none"):
        from rosbags.rosbag1 import Writer
        from rosbags.typesys import Stores, get_typestore

        self.laser = laser
        self.truth_frame = truth_frame
        self.store = get_typestore(Stores.ROS1_NOETIC)
        if TF_TYPE not in self.store.types:  # not in rosbags' noetic store
            from rosbags.typesys import get_types_from_msg
            self.store.register(get_types_from_msg(TF_DEFINITION, TF_TYPE))
        self.types = self.store.types
        self._stack = contextlib.ExitStack()
        tmp = self._stack.enter_context(atomic_path(path, suffix=".bag"))
        tmp.unlink()  # the writer refuses to overwrite
        self._writer = Writer(tmp)
        if compression != "none":
            self._writer.set_compression(Writer.CompressionFormat[compression.upper()])
        self._writer.open()
        self._conns = {topic: self._writer.add_connection(topic, msgtype, typestore=self.store)
                       for topic, msgtype in TOPIC_TYPES.items()}
        self._seq = {topic: 0 for topic in TOPIC_TYPES}
        self.messages = 0

    def write(self, step: StepMessages) -> None:
        """All messages of one step."""
        stamp = self.types["builtin_interfaces/msg/Time"](sec=step.sec, nanosec=step.nsec)
        self._put("/tf", step, self.types[TF_TYPE](
            transforms=[self._transform(tr, stamp) for tr in step.transforms]))
        self._put(ODOM_TOPIC, step, self._odometry(stamp, ODOM_TOPIC, ODOM_FRAME,
                                                   step.odom_pose, step.odom_twist))
        self._put(TRUTH_TOPIC, step, self._odometry(stamp, TRUTH_TOPIC, self.truth_frame,
                                                    step.true_pose, step.true_twist))
        if step.ranges is not None:
            self._put(SCAN_TOPIC, step, self._scan(stamp, step.ranges))

    def close(self) -> None:
        """Finish the bag and rename it onto its final name."""
        self._writer.close()
        self._stack.close()

    def abort(self) -> None:
        """Drop the partial bag."""
        with contextlib.suppress(Exception):
            self._writer.close()
        self._stack.__exit__(InterruptedError, InterruptedError("aborted"), None)

    # -- messages --------------------------------------------------------------------------
    def _put(self, topic: str, step: StepMessages, msg) -> None:
        conn = self._conns[topic]
        data = self.store.serialize_ros1(msg, conn.msgtype)
        self._writer.write(conn, step.sec * 1_000_000_000 + step.nsec, data)
        self._seq[topic] += 1
        self.messages += 1

    def _header(self, topic: str, stamp, frame_id: str):
        return self.types["std_msgs/msg/Header"](seq=self._seq[topic], stamp=stamp,
                                                 frame_id=frame_id)

    def _transform(self, tr, stamp):
        t = self.types
        return t["geometry_msgs/msg/TransformStamped"](
            header=t["std_msgs/msg/Header"](seq=0, stamp=stamp, frame_id=tr.parent),
            child_frame_id=tr.child,
            transform=t["geometry_msgs/msg/Transform"](
                translation=t["geometry_msgs/msg/Vector3"](*tr.translation),
                rotation=t["geometry_msgs/msg/Quaternion"](*tr.rotation)))

    def _odometry(self, stamp, topic: str, frame_id: str, pose, twist):
        t = self.types
        q = (float(v) for v in yaw_to_quaternion(float(pose[2])))
        pose_msg = t["geometry_msgs/msg/Pose"](
            position=t["geometry_msgs/msg/Point"](x=float(pose[0]), y=float(pose[1]), z=0.0),
            orientation=t["geometry_msgs/msg/Quaternion"](*q))
        twist_msg = t["geometry_msgs/msg/Twist"](
            linear=t["geometry_msgs/msg/Vector3"](x=float(twist[0]), y=float(twist[1]), z=0.0),
            angular=t["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=float(twist[2])))
        zeros = np.zeros(36, dtype=np.float64)
        return t["nav_msgs/msg/Odometry"](
            header=self._header(topic, stamp, frame_id), child_frame_id=FOOTPRINT_FRAME,
            pose=t["geometry_msgs/msg/PoseWithCovariance"](pose=pose_msg, covariance=zeros),
            twist=t["geometry_msgs/msg/TwistWithCovariance"](twist=twist_msg, covariance=zeros))

    def _scan(self, stamp, ranges: np.ndarray):
        d = self.laser
        ranges = np.asarray(ranges, dtype=np.float32)
        return self.types["sensor_msgs/msg/LaserScan"](
            header=self._header(SCAN_TOPIC, stamp, d.frame_id), angle_min=d.angle_min,
            angle_max=d.angle_max, angle_increment=d.angle_increment,
            time_increment=d.time_increment, scan_time=d.scan_time, range_min=d.range_min,
            range_max=d.range_max, ranges=ranges, intensities=d.intensities(ranges))
