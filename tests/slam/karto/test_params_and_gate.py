"""Karto parameters (slam_toolbox names, strict) and the scan acceptance rules."""
import math

import numpy as np
import pytest

from slam_predict import slam
from slam_predict.errors import InputError
from slam_predict.slam import LaserGeometry
from slam_predict.slam.karto.backend import Mapper, ScanGate, range_finder
from slam_predict.slam.karto.params import KartoParams
from slam_predict.slam.karto.scan import LocalizedScan


def test_config_file_is_the_defaults(root):
    assert slam.load_params("karto", root / "config" / "karto.yaml") == KartoParams()


@pytest.mark.parametrize("bad", [{"resolution": 0.0}, {"scan_buffer_size": 0},
                                 {"minimum_travel_distnce": 0.5}, {"type": "gmapping"},
                                 {"scan_gate": "fast"}, {"occupancy_threshold": 2.0}])
def test_bad_parameter_is_a_one_line_input_error(bad):
    with pytest.raises(InputError) as info:
        slam.params_from_dict("karto", bad, "karto.yaml")
    assert "karto.yaml" in str(info.value) and "\n" not in str(info.value)


def test_sync_gate_is_slam_toolboxs_should_process_scan():
    gate = ScanGate(KartoParams())
    assert gate.passes(0, 0.0, (0, 0, 0))
    assert not gate.passes(3, 10.0, (5, 0, 0))        # sequence < 5
    assert not gate.passes(6, 0.3, (5, 0, 0))         # < minimum_time_interval
    assert not gate.passes(7, 10.0, (0.4, 0, 3.0))    # 0.16 < 0.8 * 0.25, heading ignored
    assert gate.passes(8, 10.0, (0.45, 0, 0))         # 0.2025 >= 0.2


def test_has_moved_enough_uses_sensor_poses_and_heading():
    p = KartoParams()
    mapper = Mapper(p, range_finder(LaserGeometry(np.linspace(-1, 1, 5), (0.5, 0, 0), 10.0),
                                    p.max_laser_range))
    first = LocalizedScan(mapper.laser, 0, 0.0, np.zeros(3), np.ones(5))
    turned = LocalizedScan(mapper.laser, 1, 0.0, np.array([0.0, 0.0, 0.6]), np.ones(5))
    small = LocalizedScan(mapper.laser, 2, 0.0, np.array([0.0, 0.0, 0.4]), np.ones(5))
    assert mapper.has_moved_enough(first, None)
    assert mapper.has_moved_enough(turned, first)
    # 0.4 rad about the base moves a 0.5 m offset laser 0.198 m: not enough
    assert not mapper.has_moved_enough(small, first)
    far = LocalizedScan(mapper.laser, 3, 0.0, np.array([0.0, 0.0, math.pi]), np.ones(5))
    assert mapper.has_moved_enough(far, first)


def test_readings_beyond_the_threshold_are_not_points():
    laser = range_finder(LaserGeometry(np.linspace(-1, 1, 3), (0, 0, 0), 30.0), 20.0)
    scan = LocalizedScan(laser, 0, 0.0, np.zeros(3), np.array([1.0, 25.0, 2.0]))
    assert laser.range_threshold == 20.0 and scan.in_range.tolist() == [True, False, True]
