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
    """The snap target is the nearest cell centre farther than start_clearance from every
    occupied cell centre (brute force), and the footprint there is free at every yaw."""
    from slam_predict.sim.raycast import LaserGrid
    from slam_predict.world.start import start_clearance

    base = two_rooms()
    world = resolve_start(base, [-2.95, 1.95, 10.0], snap=True)
    occupied = base.cell_to_world(np.argwhere(base.occupied))
    free = base.cell_to_world(np.argwhere(~base.occupied))
    nearest_wall = np.array([np.hypot(*(occupied - c).T).min() for c in free])
    ok = free[nearest_wall > start_clearance(base)]
    best = ok[np.argmin(np.hypot(*(ok - [-2.95, 1.95]).T))]
    assert np.allclose(world.start_pose[:2], best)
    grid = LaserGrid.of_world(world)
    x, y = world.start_pose[:2]
    assert not any(grid.collides(x, y, yaw, world.robot.footprint_side)
                   for yaw in np.linspace(0.0, np.pi, 13))
    assert np.isclose(world.start_pose[2], np.radians(10.0))


def test_cell_world_round_trip():
    world = two_rooms()
    cells = np.array([[0, 0], [39, 59], [20, 30]])
    assert np.array_equal(world.world_to_cell(world.cell_to_world(cells)), cells)
