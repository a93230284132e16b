"""The start-pose rule: default, explicit, snapping and errors."""
import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.world.model import World
from slam_predict.world.start import default_start, resolve_start


def two_rooms():
    occ = np.ones((40, 60), bool)
    occ[5:35, 5:25] = False     # room A: 20 x 30 cells
    occ[10:30, 30:55] = False   # room B: 25 x 20 cells
    occ[18:22, 25:30] = False   # door
    return World("two", occ, 0.1)


def test_default_is_largest_clearance_cell():
    world = two_rooms()
    pose = default_start(world)
    row, col = world.world_to_cell(pose[:2])
    assert not world.occupied[row, col]
    # room A's centre has clearance 1.0 m (10 cells); room B's 1.0 too but comes later
    assert 5 <= col < 25 and pose[2] == 0.0


def test_explicit_start_in_degrees():
    world = resolve_start(two_rooms(), [-1.0, 0.0, 90.0])
    assert np.allclose(world.start_pose, [-1.0, 0.0, np.pi / 2])


def test_start_in_wall_or_outside_is_an_error():
    with pytest.raises(InputError, match="inside a wall"):
        resolve_start(two_rooms(), [-2.95, 1.95])
    with pytest.raises(InputError, match="outside the map"):
        resolve_start(two_rooms(), [100.0, 0.0])


def test_snap_moves_to_nearest_clear_cell():
    world = resolve_start(two_rooms(), [-2.95, 1.95, 10.0], snap=True)
    row, col = world.world_to_cell(world.start_pose[:2])
    assert not world.occupied[row, col]
    assert np.hypot(*(world.start_pose[:2] - [-2.95, 1.95])) < 0.9
    clear = np.hypot(*(world.start_pose[:2] - [-2.5, 1.5]))  # room corner
    assert clear >= 0.15
    assert np.isclose(world.start_pose[2], np.radians(10.0))


def test_cell_world_round_trip():
    world = two_rooms()
    cells = np.array([[0, 0], [39, 59], [20, 30]])
    assert np.array_equal(world.world_to_cell(world.cell_to_world(cells)), cells)
