"""Laser ray casting vs slow references (exact slab method, GEOS, fine stepping)."""
from __future__ import annotations

import numpy as np
import pytest
from ray_reference import fine_step_ranges, geos_ranges, occupied_geometry, slab_ranges
from sim_worlds import box_world, office_world, random_free_poses

from slam_predict.sim import raycast
from slam_predict.sim.raycast import GridFrame
from slam_predict.world.bitmap import load_occupancy
from slam_predict.world.model import World

ANGLES = np.deg2rad(np.linspace(-135.0, 135.0, 541))
IPA_MAPS = ("Freiburg79_scan", "NLB", "lab_a_scan", "lab_b_scan", "lab_c_scan", "lab_intel",
            "lab_ipa", "office_a", "office_b", "office_c", "office_d", "office_e", "office_h")


_GRIDS = {}


def cast(world: World, pose, angles=ANGLES, range_max=30.0) -> np.ndarray:
    key = (world.name, world.shape, world.resolution, world.origin)
    if key not in _GRIDS:
        _GRIDS[key] = raycast.LaserGrid.of_world(world)
    return _GRIDS[key].scan_angles(pose, angles, range_max).astype(float)


def test_beam_to_wall_of_empty_box_is_exact():
    world = box_world(10.0, 6.0, res=0.05, wall_px=2)  # inner walls at x = ±4.9, y = ±2.9
    pose = np.array([1.0, 0.5, 0.0])
    angles = np.array([0.0, np.pi / 2, -np.pi / 2, np.pi / 4])
    r = cast(world, pose, angles)
    assert r[0] == pytest.approx(3.9, abs=1e-5)
    assert r[1] == pytest.approx(2.4, abs=1e-5)
    assert r[2] == pytest.approx(3.4, abs=1e-5)
    assert r[3] == pytest.approx(2.4 * np.sqrt(2), abs=1e-5)


def test_jump_table_is_a_safe_lower_bound():
    """Brute force: every point of a cell is ≥ jump from every occupied cell (and outside)."""
    rng = np.random.default_rng(8)
    occ = rng.random((30, 40)) < 0.03
    jump = raycast.jump_table(occ)
    rows, cols = occ.shape
    obstacles = np.argwhere(np.pad(occ, 1, constant_values=True)) - 1  # ring = outside
    for r, c in np.argwhere(~occ)[::7]:
        # nearest distance between the two unit squares, over all obstacle cells
        gap_r = np.maximum(np.abs(obstacles[:, 0] - r) - 1, 0)
        gap_c = np.maximum(np.abs(obstacles[:, 1] - c) - 1, 0)
        assert jump[r, c] <= np.hypot(gap_r, gap_c).min() + 1e-9
    assert np.all(jump[occ] == 0)
    assert jump.max() > 3.0  # leaps do happen


def test_leaps_do_not_change_ranges():
    world = office_world(5, size_px=(200, 300), res=0.05)
    grid = raycast.LaserGrid.of_world(world)
    plain = raycast.LaserGrid.of_world(world)
    plain.jump = np.zeros_like(plain.jump)  # the pure cell walk
    rng = np.random.default_rng(2)
    for pose in random_free_poses(world, 50, rng):
        np.testing.assert_allclose(grid.scan_angles(pose, ANGLES, 80.0),
                                   plain.scan_angles(pose, ANGLES, 80.0), atol=1e-5)


def test_max_range_when_nothing_is_hit_and_zero_inside_a_wall():
    world = box_world(10.0, 6.0, res=0.05)
    r = cast(world, np.array([0.0, 0.0, 0.0]), np.array([0.0]), range_max=2.0)
    assert r[0] == 2.0
    r = cast(world, np.array([4.97, 0.0, 0.0]), np.array([np.pi]))  # inside the east wall
    assert r[0] == 0.0


@pytest.mark.parametrize("seed,thin", [(0, False), (1, True), (2, True)])
def test_exact_against_slab_reference(seed, thin):
    world = office_world(seed, thin=thin, size_px=(120, 160), res=0.1)
    frame = GridFrame.of_world(world)
    rng = np.random.default_rng(seed)
    angles = ANGLES[::4]
    for pose in random_free_poses(world, 40, rng):
        expected = slab_ranges(world.occupied, frame, *pose, angles, 30.0)
        np.testing.assert_allclose(cast(world, pose, angles), expected, atol=2e-5)


def test_exact_against_geos():
    world = office_world(3, thin=True, size_px=(100, 140), res=0.05)
    frame = GridFrame.of_world(world)
    geometry = occupied_geometry(world.occupied, frame)
    rng = np.random.default_rng(3)
    angles = ANGLES[::8]
    for pose in random_free_poses(world, 15, rng):
        expected = geos_ranges(geometry, *pose, angles, 30.0)
        np.testing.assert_allclose(cast(world, pose, angles), expected, atol=2e-5)


def _compare_fine(world: World, poses: np.ndarray, range_max: float):
    """(beams within one cell, total beams, beams beyond a sampled wall point)."""
    frame = GridFrame.of_world(world)
    step = world.resolution / 8.0
    close = total = through = 0
    for pose in poses:
        r = cast(world, pose, ANGLES, range_max)
        ref = fine_step_ranges(world.occupied, frame.x_left, frame.y_top, frame.resolution,
                               pose[0], pose[1], pose[2], ANGLES, range_max, step)
        close += int((np.abs(r - ref) <= world.resolution).sum())
        total += r.size
        through += int((r > ref + 1e-4).sum())  # a sample inside a wall lies before r
    return close, total, through


def test_against_fine_stepping_on_test_worlds():
    rng = np.random.default_rng(11)
    close = total = through = 0
    for seed in range(4):
        world = office_world(seed, thin=seed % 2 == 1, res=0.05)
        c, t, th = _compare_fine(world, random_free_poses(world, 250, rng), 30.0)
        close, total, through = close + c, total + t, through + th
    assert through == 0
    assert close / total >= 0.995


def test_against_fine_stepping_on_ipa_floor_plans(shared_data):
    """≥ 2,000 random poses over the ipa plans at 0.05 m/px (80 m range on some)."""
    folder = shared_data / "floorplans" / "ipa"
    names = [n for n in IPA_MAPS if (folder / f"{n}.png").is_file()]
    if not names:
        pytest.skip(f"no ipa maps in {folder}")
    rng = np.random.default_rng(5)
    per_map = -(-2000 // len(names))
    close = total = through = 0
    for i, name in enumerate(names):
        world = World(name, load_occupancy(folder / f"{name}.png"), 0.05)
        range_max = 80.0 if i % 3 == 0 else 30.0
        c, t, th = _compare_fine(world, random_free_poses(world, per_map, rng), range_max)
        close, total, through = close + c, total + t, through + th
    assert total >= 2000 * ANGLES.size
    assert through == 0
    assert close / total >= 0.995
