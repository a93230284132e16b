"""Planar trajectories from ROS bags (ROS 1 .bag or ROS 2 folders), through the ``rosbags`` package.

A topic may carry ``geometry_msgs/PoseStamped``, ``PoseWithCovarianceStamped``,
``TransformStamped`` or ``nav_msgs/Odometry``; the pose time is the message's ``header.stamp``.
``/tf:parent.child`` (evo's notation) reads the direct parent → child transform from ``/tf``
(or ``/tf_static``) messages; chains of several transforms are not composed. Poses are projected
on the plane (x, y, yaw).
"""
from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path

import numpy as np

from slam_predict.errors import InputError, did_you_mean
from slam_predict.geometry import quaternion_to_yaw

POSE_TYPES = {
    "geometry_msgs/msg/PoseStamped": lambda m: (m.pose.position, m.pose.orientation),
    "geometry_msgs/msg/PoseWithCovarianceStamped":
        lambda m: (m.pose.pose.position, m.pose.pose.orientation),
    "nav_msgs/msg/Odometry": lambda m: (m.pose.pose.position, m.pose.pose.orientation),
    "geometry_msgs/msg/TransformStamped":
        lambda m: (m.transform.translation, m.transform.rotation),
}


def header_stamp(header) -> float:
    """A message header's stamp in s."""
    return header.stamp.sec + header.stamp.nanosec * 1e-9


def _planar(position, orientation) -> tuple[float, float, float]:
    yaw = quaternion_to_yaw(orientation.x, orientation.y, orientation.z, orientation.w)
    return position.x, position.y, float(yaw)


def _open(path: str):
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    reader = AnyReader([Path(path)], default_typestore=get_typestore(Stores.ROS1_NOETIC))
    try:
        reader.open()
    except Exception as exc:  # rosbags raises several reader-specific errors
        raise InputError(f"cannot open ROS bag: {exc}".splitlines()[0], path) from None
    return reader


def read_pose_topic(path: os.PathLike | str, topic: str) -> tuple[np.ndarray, np.ndarray]:
    """(t (N,) s, poses (N, 3)) of ``topic`` in the bag at ``path``, sorted by time."""
    path = os.fspath(path)
    if not os.path.exists(path):
        raise InputError("ROS bag not found", path)
    tf_frames = None
    if topic.startswith("/tf:"):
        parent, _, child = topic[4:].partition(".")
        if not parent or not child:
            raise InputError(f"bad TF topic {topic!r}: use /tf:parent.child", path)
        tf_frames = (parent.lstrip("/"), child.lstrip("/"))
    reader = _open(path)
    try:
        return _read(reader, path, topic, tf_frames)
    finally:
        reader.close()


def _read(reader, path: str, topic: str, tf_frames) -> tuple[np.ndarray, np.ndarray]:
    wanted = ("/tf", "/tf_static") if tf_frames else (topic,)
    connections = [c for c in reader.connections if c.topic in wanted]
    if not connections:
        topics = sorted({c.topic for c in reader.connections})
        raise InputError(f"topic {wanted[0]} not in bag{did_you_mean(wanted[0], topics)}; "
                         f"topics: {', '.join(topics)}", path)
    rows = []
    for conn, _, raw in reader.messages(connections=connections):
        msg = reader.deserialize(raw, conn.msgtype)
        if tf_frames:
            rows.extend(_tf_rows(msg, tf_frames))
            continue
        if conn.msgtype not in POSE_TYPES:
            raise InputError(f"topic {topic} has type {conn.msgtype}; supported: "
                             f"{', '.join(sorted(POSE_TYPES))}", path)
        rows.append((header_stamp(msg.header), *_planar(*POSE_TYPES[conn.msgtype](msg))))
    if not rows:
        raise InputError(f"no poses on {topic}", path)
    data = np.array(rows, dtype=float)
    data = data[np.argsort(data[:, 0], kind="stable")]
    return data[:, 0], data[:, 1:4]


def _tf_rows(msg, frames) -> Iterable[tuple]:
    parent, child = frames
    for tr in msg.transforms:
        if tr.header.frame_id.lstrip("/") == parent and tr.child_frame_id.lstrip("/") == child:
            yield (header_stamp(tr.header),
                   *_planar(tr.transform.translation, tr.transform.rotation))


def write_pose_bag(path: os.PathLike | str, topics: dict[str, tuple[np.ndarray, np.ndarray]],
                   frame_id: str = "map") -> None:
    """Write a ROS 1 bag with one ``geometry_msgs/PoseStamped`` topic per entry of ``topics``.

    ``topics`` maps a topic name to (t (N,) s, poses (N, 3)). The bag is written to a temporary
    name and renamed (atomic).
    """
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    from slam_predict.atomic import atomic_path

    store = get_typestore(Stores.ROS1_NOETIC)
    types = store.types
    with atomic_path(path, suffix=".bag") as tmp:
        tmp.unlink()  # the writer refuses to overwrite
        with Writer(tmp) as writer:
            for topic, (t, poses) in topics.items():
                conn = writer.add_connection(topic, "geometry_msgs/msg/PoseStamped",
                                             typestore=store)
                stamped = zip(np.asarray(t, float), np.asarray(poses, float), strict=False)
                for seq, (ti, pose) in enumerate(stamped):
                    msg = _pose_stamped(types, seq, ti, pose, frame_id)
                    stamp_ns = int(round(ti * 1e9))
                    writer.write(conn, stamp_ns, store.serialize_ros1(msg, conn.msgtype))


def _pose_stamped(types, seq: int, t: float, pose, frame_id: str):
    sec = int(np.floor(t))
    nanosec = int(round((t - sec) * 1e9))
    if nanosec >= 1_000_000_000:
        sec, nanosec = sec + 1, nanosec - 1_000_000_000
    header = types["std_msgs/msg/Header"](seq=seq, stamp=types["builtin_interfaces/msg/Time"](
        sec=sec, nanosec=nanosec), frame_id=frame_id)
    half = pose[2] / 2.0
    position = types["geometry_msgs/msg/Point"](x=float(pose[0]), y=float(pose[1]), z=0.0)
    orientation = types["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=float(np.sin(half)),
                                                        w=float(np.cos(half)))
    return types["geometry_msgs/msg/PoseStamped"](
        header=header, pose=types["geometry_msgs/msg/Pose"](position=position,
                                                            orientation=orientation))
