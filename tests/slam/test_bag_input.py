"""ROS bag input: LaserScan + tf (or Odometry) from a synthetic bag written with rosbags."""
import math

import numpy as np
import pytest
from slam_synthetic import cast

from slam_predict.cli.main import main
from slam_predict.errors import InputError
from slam_predict.formats.tum import read_tum
from slam_predict.geometry import compose
from slam_predict.slam.bag_input import read_bag_input

ANGLES = np.radians(np.linspace(-120.0, 120.0, 241))
TFMSG = "geometry_msgs/TransformStamped[] transforms"


def truth(t):
    """Robot pose (odom = truth here) at time t s: a slow arc through the synthetic room."""
    return np.array([-3.0 + 0.3 * t, -2.0 + 0.1 * t, 0.1 * math.sin(0.5 * t)])


def write_bag(path, upside_down=False, seconds=12.0):
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC)
    store.register(get_types_from_msg(TFMSG, "tf2_msgs/msg/TFMessage"))
    T = store.types

    def header(t, frame, seq=0):
        sec = int(math.floor(t))
        return T["std_msgs/msg/Header"](seq=seq, stamp=T["builtin_interfaces/msg/Time"](
            sec=sec, nanosec=int(round((t - sec) * 1e9))), frame_id=frame)

    def transform(t, parent, child, x, y, z, q):
        return T["geometry_msgs/msg/TransformStamped"](
            header=header(t, parent), child_frame_id=child,
            transform=T["geometry_msgs/msg/Transform"](
                translation=T["geometry_msgs/msg/Vector3"](x=x, y=y, z=z),
                rotation=T["geometry_msgs/msg/Quaternion"](x=q[0], y=q[1], z=q[2], w=q[3])))

    def yaw_q(yaw):
        return (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))

    roll = (1.0, 0.0, 0.0, 0.0) if upside_down else (0.0, 0.0, 0.0, 1.0)
    with Writer(path) as writer:
        c_scan = writer.add_connection("/base_scan", "sensor_msgs/msg/LaserScan", typestore=store)
        c_tf = writer.add_connection("/tf", "tf2_msgs/msg/TFMessage", typestore=store)
        c_static = writer.add_connection("/tf_static", "tf2_msgs/msg/TFMessage", typestore=store)
        c_odom = writer.add_connection("/odom", "nav_msgs/msg/Odometry", typestore=store)

        def put(conn, t, msg):
            writer.write(conn, int(round(t * 1e9)), store.serialize_ros1(msg, conn.msgtype))

        statics = [transform(0.0, "base_footprint", "base_link", 0.0, 0.0, 0.0, yaw_q(0.0)),
                   transform(0.0, "base_link", "laser", 0.1, 0.0, 0.2, roll)]
        put(c_static, 0.0, T["tf2_msgs/msg/TFMessage"](transforms=statics))
        for k in range(int(seconds * 20) + 1):
            t = 0.05 * k
            p = truth(t)
            put(c_tf, t, T["tf2_msgs/msg/TFMessage"](transforms=[
                transform(t, "odom", "base_footprint", p[0], p[1], 0.0, yaw_q(p[2]))]))
            pose = T["geometry_msgs/msg/PoseWithCovariance"](
                pose=T["geometry_msgs/msg/Pose"](
                    position=T["geometry_msgs/msg/Point"](x=p[0], y=p[1], z=0.0),
                    orientation=T["geometry_msgs/msg/Quaternion"](*yaw_q(p[2]))),
                covariance=np.zeros(36))
            twist = T["geometry_msgs/msg/TwistWithCovariance"](
                twist=T["geometry_msgs/msg/Twist"](
                    linear=T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0),
                    angular=T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0)),
                covariance=np.zeros(36))
            put(c_odom, t, T["nav_msgs/msg/Odometry"](header=header(t, "odom"),
                                                      child_frame_id="base_footprint",
                                                      pose=pose, twist=twist))
        for k in range(int(seconds * 10) + 1):
            # between tf samples (interpolation); the last one after the tf ends (dropped)
            t = 0.1 * k + 0.025 if k < int(seconds * 10) else seconds + 0.5
            laser = compose(truth(t), np.array([0.1, 0.0, 0.0]))
            ranges = cast(laser, ANGLES).astype(np.float32)
            ranges[5] = 0.01  # below range_min -> range_max
            if upside_down:
                ranges = ranges[::-1].copy()
            msg = T["sensor_msgs/msg/LaserScan"](
                header=header(t, "laser", k), angle_min=float(ANGLES[0]),
                angle_max=float(ANGLES[-1]), angle_increment=float(ANGLES[1] - ANGLES[0]),
                time_increment=0.0, scan_time=0.1, range_min=0.05, range_max=30.0,
                ranges=ranges, intensities=np.zeros(0, np.float32))
            put(c_scan, t, msg)


@pytest.mark.parametrize("upside_down", [False, True])
def test_bag_scans_get_interpolated_odometry_and_the_laser_mount(tmp_path, upside_down):
    bag = tmp_path / "drive.bag"
    write_bag(bag, upside_down)
    data = read_bag_input(bag, base_frame="base_footprint")
    assert len(data) == 120 and data.info["scans_in_log"] == 121  # no odometry for the last
    expected = np.array([truth(t) for t in data.times])
    assert np.allclose(data.odometry[:, :2], expected[:, :2], atol=2e-3)
    assert np.allclose(data.odometry[:, 2], expected[:, 2], atol=2e-3)
    assert data.laser.pose_in_base == pytest.approx((0.1, 0.0, 0.0))
    assert np.allclose(data.laser.angles, ANGLES, atol=1e-6)
    assert data.info["reversed"] is upside_down and data.reference is None
    k = 7
    laser = compose(truth(data.times[k]), np.array([0.1, 0.0, 0.0]))
    want = cast(laser, ANGLES)
    want[5] = 30.0
    assert np.allclose(data.ranges[k], want, atol=1e-5)
    via_topic = read_bag_input(bag, odom_topic="/odom", base_frame="base_footprint")
    assert np.allclose(via_topic.odometry, data.odometry, atol=1e-9)


def test_bag_errors_are_input_errors(tmp_path):
    bag = tmp_path / "drive.bag"
    write_bag(bag, seconds=2.0)
    with pytest.raises(InputError, match="did you mean '/base_scan'"):
        read_bag_input(bag, scan_topic="/base_scn")
    with pytest.raises(InputError, match="no tf from map"):
        read_bag_input(bag, base_frame="map")
    with pytest.raises(InputError, match="not nav_msgs/msg/Odometry"):
        read_bag_input(bag, odom_topic="/base_scan")


def test_cli_runs_on_a_bag(tmp_path):
    bag = tmp_path / "drive.bag"
    write_bag(bag)
    out = tmp_path / "run"
    cfg = tmp_path / "gm.yaml"
    cfg.write_text("particles: 10\nlinearUpdate: 0.3\nangularUpdate: 0.2\n")
    assert main(["slam", "run", str(bag), "--base-frame", "base_footprint", "--out", str(out),
                 "--seed", "1", "--config", str(cfg)]) == 0
    t, poses = read_tum(out / "slam.tum")
    assert len(t) > 5 and np.allclose(poses[0], truth(t[0]), atol=1e-6)
    assert np.max(np.hypot(*(poses - np.array([truth(v) for v in t]))[:, :2].T)) < 0.1
