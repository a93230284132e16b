"""SLAM input from a ROS bag (ROS 1 .bag or ROS 2 folder, read with ``rosbags``), the way
slam_gmapping would see it live.

- Scans: the ``sensor_msgs/LaserScan`` topic (``scan_topic``; default: the bag's only one).
- Odometry: tf ``odom_frame → base_frame`` at each scan's stamp (``/tf`` chains composed, each
  dynamic link interpolated linearly in time, as tf does), or the poses of a
  ``nav_msgs/Odometry`` topic (``odom_topic``) interpolated the same way. Scans outside the
  odometry's time span are dropped, as slam_gmapping drops scans whose tf is not available.
- Laser mounting: tf ``base_frame → scan frame`` (from ``/tf_static`` or ``/tf``), which must be
  planar; readings below range_min become range_max; scans running clockwise are reversed.
- Reference trajectory: stage_ros' ``/base_pose_ground_truth`` (nav_msgs/Odometry) at the
  scans' stamps, when the bag has it (e.g. a collected run's ``sensors.bag``); else none.
"""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from slam_predict.errors import InputError, did_you_mean
from slam_predict.formats.rosbag import header_stamp
from slam_predict.slam.laser import laser_geometry, prepare_ranges, quaternion_matrix
from slam_predict.slam.scans import SlamInput

SCAN_TYPE = "sensor_msgs/msg/LaserScan"
ODOM_TYPE = "nav_msgs/msg/Odometry"
TF_TOPICS = ("/tf", "/tf_static")
TRUTH_TOPIC = "/base_pose_ground_truth"


def _frame(name: str) -> str:
    return name.lstrip("/")


class TfTree:
    """Transforms parent → child from tf messages: static, or dynamic samples over time."""

    def __init__(self):
        self.parent: dict[str, str] = {}
        self.samples: dict[str, list[tuple[float, np.ndarray]]] = {}
        self.static: dict[str, np.ndarray] = {}
        self._times: dict[str, np.ndarray] = {}   # sample times per child, rebuilt after adds

    def add(self, parent: str, child: str, t: float, value: np.ndarray, static: bool) -> None:
        """One transform: ``value`` = (tx, ty, tz, qx, qy, qz, qw)."""
        self.parent[child] = parent
        if static:
            self.static[child] = value
        else:
            self.samples.setdefault(child, []).append((t, value))
            self._times.pop(child, None)

    def _sample_times(self, child: str) -> np.ndarray:
        if child not in self._times:
            self._times[child] = np.array([r[0] for r in self.samples[child]])
        return self._times[child]

    def _link(self, child: str, t: float) -> np.ndarray | None:
        """The link at ``t``: a sample stamped exactly ``t`` unchanged (as tf returns it),
        else interpolated between the samples around ``t``."""
        if child in self.static:
            return self.static[child]
        rows = self.samples[child]
        times = self._sample_times(child)
        if t < times[0] - 1e-9 or t > times[-1] + 1e-9:
            return None
        k = int(np.searchsorted(times, t))
        if k < len(times) and times[k] == t:
            return rows[k][1]
        k = int(np.clip(k, 1, len(times) - 1)) if len(times) > 1 else 0
        a, b = rows[max(k - 1, 0)], rows[k]
        w = 0.0 if b[0] == a[0] else (t - a[0]) / (b[0] - a[0])
        return _interpolate(a[1], b[1], float(np.clip(w, 0.0, 1.0)))

    def lookup(self, parent: str, child: str, t: float):
        """(translation (3,), rotation 3 x 3) of ``child`` in ``parent`` at ``t`` s, or None when
        ``parent`` is not an ancestor of ``child`` or ``t`` is outside a link's samples."""
        rotation, translation = np.eye(3), np.zeros(3)
        frame = child
        while frame != parent:
            if frame not in self.parent:
                return None
            value = self._link(frame, t)
            if value is None:
                return None
            r = quaternion_matrix(*value[3:7])
            translation = r @ translation + value[:3]
            rotation = r @ rotation
            frame = self.parent[frame]
        return translation, rotation


def _interpolate(a: np.ndarray, b: np.ndarray, w: float) -> np.ndarray:
    """Linear translation, normalised-linear quaternion (close to slerp for small steps)."""
    qa, qb = a[3:7], b[3:7]
    if np.dot(qa, qb) < 0:
        qb = -qb
    q = (1 - w) * qa + w * qb
    return np.concatenate([(1 - w) * a[:3] + w * b[:3], q / np.linalg.norm(q)])


def _value(transform) -> np.ndarray:
    t, q = transform.translation, transform.rotation
    return np.array([t.x, t.y, t.z, q.x, q.y, q.z, q.w], dtype=float)


def _planar_from_matrix(translation: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    return np.array([translation[0], translation[1], np.arctan2(rotation[1, 0], rotation[0, 0])])


def _pick_topic(reader, path: str, topic: str | None, msgtype: str, what: str) -> str:
    topics = {c.topic: c.msgtype for c in reader.connections}
    if topic is not None:
        if topic not in topics:
            raise InputError(f"{what} topic {topic} not in bag{did_you_mean(topic, topics)}", path)
        if topics[topic] != msgtype:
            raise InputError(f"topic {topic} has type {topics[topic]}, not {msgtype}", path)
        return topic
    found = sorted(t for t, kind in topics.items() if kind == msgtype)
    if len(found) != 1:
        raise InputError(f"{len(found)} {msgtype} topics in bag ({', '.join(found) or 'none'}): "
                         f"choose the {what} topic", path)
    return found[0]


def read_bag_input(path: os.PathLike | str, scan_topic: str | None = None,
                   odom_topic: str | None = None, base_frame: str = "base_link",
                   odom_frame: str = "odom", max_scans: int | None = None) -> SlamInput:
    """A :class:`SlamInput` from a bag (see the module docstring)."""
    from slam_predict.formats.rosbag import _open

    path = os.fspath(path)
    if not os.path.exists(path):
        raise InputError("ROS bag not found", path)
    reader = _open(path)
    try:
        scan_topic = _pick_topic(reader, path, scan_topic, SCAN_TYPE, "scan")
        if odom_topic is not None:
            odom_topic = _pick_topic(reader, path, odom_topic, ODOM_TYPE, "odometry")
        truth_topic = TRUTH_TOPIC if any(c.topic == TRUTH_TOPIC and c.msgtype == ODOM_TYPE
                                         for c in reader.connections) else None
        scans, tree, poses = _read_messages(reader, scan_topic, (odom_topic, truth_topic))
    finally:
        reader.close()
    if not scans:
        raise InputError(f"no scans on {scan_topic}", path)
    data = _assemble(path, scans, tree, poses[odom_topic], base_frame, odom_frame, max_scans)
    if truth_topic is not None:
        data.reference = _poses_at(poses[truth_topic], data.times)
        data.info["reference"] = truth_topic if data.reference is not None else None
    return data


def _read_messages(reader, scan_topic: str, pose_topics):
    """(scans sorted by stamp, tf tree, {pose topic: [(stamp, tf value)] sorted})."""
    pose_topics = [t for t in pose_topics if t is not None]
    wanted = {scan_topic, *TF_TOPICS, *pose_topics}
    connections = [c for c in reader.connections if c.topic in wanted]
    scans = []
    poses = {None: [], **{topic: [] for topic in pose_topics}}
    tree = TfTree()
    for conn, _, raw in reader.messages(connections=connections):
        msg = reader.deserialize(raw, conn.msgtype)
        if conn.topic == scan_topic:
            scans.append(msg)
        elif conn.topic in poses:
            p = msg.pose.pose
            value = np.array([p.position.x, p.position.y, p.position.z, p.orientation.x,
                              p.orientation.y, p.orientation.z, p.orientation.w])
            poses[conn.topic].append((header_stamp(msg.header), value))
        else:
            for tr in msg.transforms:
                tree.add(_frame(tr.header.frame_id), _frame(tr.child_frame_id),
                         header_stamp(tr.header), _value(tr.transform),
                         conn.topic == "/tf_static")
    scans.sort(key=lambda m: header_stamp(m.header))
    for rows in poses.values():
        rows.sort(key=lambda row: row[0])
    return scans, tree, poses


def _poses_at(samples, times: np.ndarray) -> np.ndarray | None:
    """Planar poses of an Odometry topic's samples at ``times`` (None if one is outside)."""
    tree = TfTree()
    for t, value in samples:
        tree.add("world", "robot", t, value, static=False)
    if not samples:
        return None
    out = [odometry_pose(tree, "world", "robot", float(t)) for t in times]
    return None if any(p is None for p in out) else np.array(out)


def _assemble(path, scans, tree: TfTree, odom, base_frame, odom_frame, max_scans) -> SlamInput:
    first = scans[0]
    laser_frame = _frame(first.header.frame_id)
    laser, reverse = mounted_laser(tree, base_frame, laser_frame, header_stamp(first.header),
                                   first.angle_min, first.angle_increment, len(first.ranges),
                                   first.range_max, path)
    source = TfTree()
    for t, value in odom:
        source.add(odom_frame, base_frame, t, value, static=False)
    if not odom:
        source = tree
    times, poses, ranges = [], [], []
    for msg in scans:
        t = header_stamp(msg.header)
        pose = odometry_pose(source, odom_frame, base_frame, t)
        if pose is None or len(msg.ranges) != laser.beams:
            continue
        times.append(t)
        poses.append(pose)
        ranges.append(prepare_ranges(msg.ranges, msg.range_min, msg.range_max, reverse))
        if max_scans is not None and len(times) >= max_scans:
            break
    if not times:
        raise InputError(f"no scan has an odometry pose ({odom_frame} -> {base_frame})", path)
    return SlamInput(path=path, times=np.array(times), odometry=np.array(poses),
                     ranges=np.array(ranges), laser=laser, reference=None,
                     info={"format": "rosbag", "scans_in_log": len(scans),
                           "scans_with_odometry": len(times), "laser_frame": laser_frame,
                           "base_frame": base_frame, "odom_frame": odom_frame,
                           "reversed": reverse, "laser_offset_m": laser.pose_in_base[0]})


def mounted_laser(tree: TfTree, base_frame: str, laser_frame: str, t: float, angle_min: float,
                  angle_increment: float, beams: int, range_max: float, path=None):
    """(laser geometry in the base frame, reverse flag) from the tf link base → laser at ``t``
    and a LaserScan's fields, as slam_gmapping sets up its laser on the first scan."""
    mount = tree.lookup(base_frame, laser_frame, t)
    if mount is None:
        raise InputError(f"no tf from {base_frame} to the laser frame {laser_frame}", path)
    laser, reverse = laser_geometry(mount[1], mount[0], angle_min, angle_increment, beams,
                                    range_max)
    if laser is None:
        raise InputError("the laser is not mounted planar (slam_gmapping needs it level)", path)
    return laser, reverse


def odometry_pose(tree: TfTree, odom_frame: str, base_frame: str, t: float):
    """Planar pose (x, y, yaw) of ``base_frame`` in ``odom_frame`` at ``t``, or None."""
    found = tree.lookup(odom_frame, base_frame, t)
    return None if found is None else _planar_from_matrix(*found)


class LiveDecoder:
    """What slam_gmapping receives from the messages of
    :mod:`slam_predict.formats.stage_stream`, decoded exactly as :func:`read_bag_input` decodes
    the same messages read back from a bag (same stamps, tf lookups and range clean-up), so a
    replay of the bag is bit-identical. ``laser``: a
    :class:`~slam_predict.formats.stage_stream.LaserDescription`."""

    def __init__(self, laser, base_frame: str = "base_link", odom_frame: str = "odom"):
        from slam_predict.formats.stage_stream import scan_transforms

        self.description = laser
        self.base_frame, self.odom_frame = base_frame, odom_frame
        tree = _tree(scan_transforms(laser, (0.0, 0.0, 0.0)), 0.0)
        self.laser, self.reverse = mounted_laser(
            tree, base_frame, laser.frame_id, 0.0, laser.angle_min, laser.angle_increment,
            laser.beams, laser.range_max)

    def odometry(self, messages) -> np.ndarray:
        """The odometry pose (x, y, yaw) of ``base_frame`` at the messages' stamp."""
        t = messages.t
        return odometry_pose(_tree(messages.transforms, t), self.odom_frame, self.base_frame, t)

    def scan(self, messages) -> tuple[np.ndarray, np.ndarray, float]:
        """(odometry pose, float64 ranges, stamp s) of a step that carries a scan."""
        d = self.description
        ranges = prepare_ranges(messages.ranges, d.range_min, d.range_max, self.reverse)
        return self.odometry(messages), ranges, messages.t


def _tree(transforms, t: float) -> TfTree:
    tree = TfTree()
    for tr in transforms:
        tree.add(tr.parent, tr.child, t, tr.value, static=False)
    return tree


def bag_like(path: os.PathLike | str) -> bool:
    """Whether ``path`` looks like a ROS bag (.bag file, .db3/.mcap, or a ROS 2 bag folder)."""
    p = Path(path)
    return p.suffix in (".bag", ".db3", ".mcap") or (p.is_dir() and (p / "metadata.yaml").exists())
