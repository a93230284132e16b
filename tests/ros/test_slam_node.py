"""The slam_gmapping node class driven through fake rospy / tf on a synthetic room."""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("nav_msgs.msg", reason="ROS message packages (nav_msgs) not installed")

from geometry_msgs.msg import TransformStamped  # noqa: E402
from sensor_msgs.msg import LaserScan  # noqa: E402

from slam_predict.geometry import compose, yaw_to_quaternion  # noqa: E402
from slam_predict.ros.conversions.geometry import time_to_ros, transform_from_ros  # noqa: E402
from slam_predict.ros.conversions.slam import grid_from_ros  # noqa: E402
from slam_predict.ros.slam_node import SlamNode, read_params  # noqa: E402
from slam_predict.slam import SlamChoice, SlamNodeParams  # noqa: E402
from slam_predict.slam.gmapping.params import GMappingParams  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "slam"))
from slam_synthetic import cast  # noqa: E402

ANGLES = np.radians(np.arange(-90.0, 90.5, 1.0))  # 181 beams, symmetric


class FakePub:
    def __init__(self):
        self.sent = []

    def publish(self, msg):
        self.sent.append(msg)


class FakeRospy:
    def __init__(self, params=None):
        self.params = params or {}
        self.pubs = {}
        self.now = 0.0

    def Publisher(self, name, _type, **_):
        return self.pubs.setdefault(name, FakePub())

    def Service(self, *_args):
        pass

    def Subscriber(self, *_args, **_):
        pass

    def has_param(self, name):
        return name in self.params

    def get_param(self, name, default=None):
        return self.params.get(name, default)

    def get_time(self):
        return self.now

    def is_shutdown(self):
        return False


class FakeTf:
    """odom -> base_link per stamp; base_link -> laser fixed (optionally upside down)."""

    def __init__(self, upside_down):
        self.odom = {}
        roll = math.pi if upside_down else 0.0
        self.laser_q = (math.sin(roll / 2), 0.0, 0.0, math.cos(roll / 2))
        self.sent = []

    def lookup_transform(self, parent, child, stamp):
        msg = TransformStamped()
        if (parent, child) == ("base_link", "laser"):
            msg.transform.translation.x = 0.1
            q = msg.transform.rotation
            q.x, q.y, q.z, q.w = self.laser_q
            return msg
        pose = self.odom[round(stamp.to_sec(), 6)]
        msg.transform.translation.x, msg.transform.translation.y = pose[0], pose[1]
        q = msg.transform.rotation
        q.x, q.y, q.z, q.w = (float(v) for v in yaw_to_quaternion(pose[2]))
        return msg

    def sendTransform(self, msg):
        self.sent.append(msg)


def drive(upside_down, steps=60, ack=False, **params):
    params = GMappingParams(particles=8, xmin=-10, ymin=-10, xmax=10, ymax=10,
                            linearUpdate=0.3, angularUpdate=0.2, map_update_interval=1.0,
                            **params)
    fake, tf = FakeRospy(), FakeTf(upside_down)
    node = SlamNode(SlamChoice("gmapping", params), SlamNodeParams(), 3, fake, tf, tf)
    node.start = None  # the wiring needs a ROS master; publishers are made below
    names = ("map", "map_metadata", "entropy") + (("ack",) if ack else ())
    node._pubs = {k: fake.Publisher(k, None) for k in names}
    known = []
    for k in range(steps):
        t = 10.0 + 0.5 * k
        base = np.array([-3.0 + 0.1 * k, -2.0 + 0.02 * k, 0.2 * math.sin(0.1 * k)])
        tf.odom[round(t, 6)] = base
        laser = compose(base, np.array([0.1, 0.0, 0.0]))
        ranges = cast(laser, ANGLES)
        if upside_down:
            ranges = ranges[::-1]  # beam i of an upside-down laser looks at bearing -angle_i
        msg = LaserScan(angle_min=ANGLES[0], angle_max=ANGLES[-1],
                        angle_increment=ANGLES[1] - ANGLES[0], range_min=0.1, range_max=30.0,
                        ranges=ranges.tolist())
        msg.header.stamp = time_to_ros(t)
        msg.header.frame_id = "laser"
        fake.now = t
        node.on_scan(msg)
        if fake.pubs["map"].sent:
            known.append((grid_from_ros(fake.pubs["map"].sent[-1]).data >= 0).sum())
    return node, fake, tf, known


def test_node_publishes_growing_maps_and_map_to_odom():
    node, fake, tf, known = drive(upside_down=False)
    maps = fake.pubs["map"].sent
    assert len(maps) >= 3 and len(fake.pubs["map_metadata"].sent) == len(maps)
    assert known[-1] > known[0] > 0
    # 400 cells floored to patches
    assert maps[-1].header.frame_id == "map" and maps[-1].info.width == 384
    node.publish_transform()
    sent = transform_from_ros(tf.sent[-1])
    assert (sent.parent, sent.child) == ("map", "odom")
    assert sent.stamp == pytest.approx(fake.now + 0.05)
    assert np.allclose(sent.pose, node.slam.map_to_odom(), atol=1e-9)
    response = node.on_get_map(None)
    assert np.array_equal(grid_from_ros(response.map).data, grid_from_ros(maps[-1]).data)


def test_every_scan_is_acked_with_its_stamp_after_it_is_handled():
    """stage_sim's lockstep waits for ~sim_ack = the stamp of each scan, processed or not
    (most scans are skipped: the robot has not moved linearUpdate/angularUpdate)."""
    _node, fake, _tf, _known = drive(upside_down=False, steps=12, ack=True)
    acks = [m.data.to_sec() for m in fake.pubs["ack"].sent]
    assert acks == pytest.approx([10.0 + 0.5 * k for k in range(12)])
    # the first map (first processed scan) was published before that scan's ack
    assert fake.pubs["map"].sent


def test_upside_down_laser_gives_the_same_map():
    a = drive(upside_down=False, steps=25)[1].pubs["map"].sent[-1]
    b = drive(upside_down=True, steps=25)[1].pubs["map"].sent[-1]
    assert np.array_equal(grid_from_ros(a).data, grid_from_ros(b).data)


def test_no_map_before_the_first_scan():
    node = SlamNode(SlamChoice("gmapping", GMappingParams()), SlamNodeParams(), 0, FakeRospy(),
                    None, None)
    assert node.on_get_map(None) is None


def test_params_come_from_the_private_namespace():
    fake = FakeRospy({"~particles": 12, "~xmin": -20, "~seed": 7, "~type": "gmapping",
                      "~base_frame": "base_footprint", "~throttle_scans": 2,
                      "~random_stream": "numpy", "~drand48_seed": 11})
    choice, node, seed = read_params(fake)
    params = choice.params
    assert choice.type == "gmapping" and isinstance(params, GMappingParams)
    assert params.particles == 12 and params.xmin == -20.0 and seed == 7
    assert (params.random_stream, params.drand48_seed) == ("numpy", 11)
    assert node.base_frame == "base_footprint" and node.throttle_scans == 2
    from slam_predict.errors import InputError
    with pytest.raises(InputError, match="particles"):
        read_params(FakeRospy({"~particles": "x"}))
    with pytest.raises(InputError, match="random_stream"):
        read_params(FakeRospy({"~random_stream": "pcg"}))
    with pytest.raises(InputError, match="unknown SLAM type 'gmaping'.*did you mean 'gmapping'"):
        read_params(FakeRospy({"~type": "gmaping"}))


def test_the_node_draws_from_the_configured_stream():
    """drand48 by default, seeded from the node's ``~seed`` generator (3 here) unless
    ``drand48_seed`` is set; ``numpy``: the node's generator itself."""
    from slam_predict.slam.gmapping.drand48 import Drand48Generator

    node, *_ = drive(upside_down=False, steps=3)
    drawn = int(np.random.default_rng(3).integers(1, 2 ** 31 - 1))
    stats = node.slam.stats()
    assert (stats["random_stream"], stats["drand48_seed"]) == ("drand48", drawn)
    assert isinstance(node.slam.filter.rng, Drand48Generator)
    node, *_ = drive(upside_down=False, steps=3, drand48_seed=11)
    assert node.slam.stats()["drand48_seed"] == node.slam.filter.rng.seed == 11
    node, *_ = drive(upside_down=False, steps=3, random_stream="numpy")
    assert isinstance(node.slam.filter.rng, np.random.Generator)
    assert node.slam.stats()["drand48_seed"] is None


@pytest.mark.parametrize("executable, given, gate", [
    ("sync_slam_toolbox_node", {}, "sync"), ("sync_slam_toolbox_node", {"~scan_gate": "none"},
                                             "sync"),
    ("async_slam_toolbox_node", {"~scan_gate": "sync"}, "async"),
    ("async_slam_toolbox_node", {"~scan_gate": "none"}, "none")])
def test_slam_toolbox_executables_run_karto_with_their_gate(executable, given, gate):
    from slam_predict.slam.karto.params import KartoParams
    fake = FakeRospy({"~resolution": 0.1, "~minimum_travel_distance": 0.3,
                      "~async_cost": {"cpu_factor": 2.0}, **given})
    choice, _node, _seed = read_params(fake, executable)
    assert choice.type == "karto" and isinstance(choice.params, KartoParams)
    assert choice.params.scan_gate == gate and choice.params.resolution == 0.1
    assert choice.params.minimum_travel_distance == 0.3
    assert choice.params.async_cost.cpu_factor == 2.0


@pytest.mark.parametrize("given, problem", [
    ({"~type": "gmapping"}, "runs only karto"), ({"~resolution": -0.05}, "resolution"),
    ({"~minimum_travel_distnce": 1.0, "~resolution": "x"}, "resolution")])
def test_slam_toolbox_executables_refuse_bad_parameters(given, problem):
    from slam_predict.errors import InputError
    with pytest.raises(InputError, match=problem):
        read_params(FakeRospy(given), "async_slam_toolbox_node")


def run_karto_node(params, poses):
    """Our node with Karto fed a scan every 0.5 s from 10 s at each base pose of ``poses``;
    returns the node, the fake rospy and tf."""
    fake, tf = FakeRospy(), FakeTf(False)
    node = SlamNode(SlamChoice("karto", params), SlamNodeParams(), 3, fake, tf, tf)
    node._pubs = {k: fake.Publisher(k, None) for k in ("map", "map_metadata", "entropy")}
    for k, base in enumerate(poses):
        t = 10.0 + 0.5 * k
        tf.odom[round(t, 6)] = base
        msg = LaserScan(angle_min=ANGLES[0], angle_max=ANGLES[-1],
                        angle_increment=ANGLES[1] - ANGLES[0], range_min=0.1, range_max=30.0,
                        ranges=cast(compose(base, np.array([0.1, 0.0, 0.0])), ANGLES).tolist())
        msg.header.stamp = time_to_ros(t)
        msg.header.frame_id = "laser"
        fake.now = t
        node.on_scan(msg)
    return node, fake, tf


def test_karto_node_publishes_maps_and_map_to_odom():
    from slam_predict.slam.karto.params import KartoParams
    params = KartoParams(xmin=-10, ymin=-10, xmax=10, ymax=10, minimum_travel_distance=0.3,
                         map_update_interval=1.0, max_laser_range=20.0)
    poses = [np.array([-3.0 + 0.1 * k, -2.0 + 0.02 * k, 0.2 * math.sin(0.1 * k)])
             for k in range(40)]
    node, fake, tf = run_karto_node(params, poses)
    maps = fake.pubs["map"].sent
    assert len(maps) >= 3 and (grid_from_ros(maps[-1]).data == 100).sum() > 50
    assert node.slam.stats()["scans_processed"] > 5
    node.publish_transform()
    sent = transform_from_ros(tf.sent[-1])
    assert (sent.parent, sent.child) == ("map", "odom")
    assert np.allclose(sent.pose, node.slam.map_to_odom(), atol=1e-9)


def test_karto_node_republishes_the_map_while_the_robot_stands_still():
    """slam_toolbox's map thread: a map every map_update_interval s without new scans."""
    from slam_predict.slam.karto.params import KartoParams
    params = KartoParams(xmin=-10, ymin=-10, xmax=10, ymax=10, map_update_interval=1.0)
    node, fake, _ = run_karto_node(params, [np.array([-3.0, -2.0, 0.1])] * 21)   # 10 s still
    assert node.slam.stats()["scans_processed"] == 1
    stamps = [m.header.stamp for m in fake.pubs["map"].sent]
    assert len(stamps) == 7                   # at 10 s, then every 1.5 s (> 1 s) up to 19 s
    assert len(fake.pubs["map_metadata"].sent) == len(stamps)
