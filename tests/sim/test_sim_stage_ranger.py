"""Stage 4.1.1 ranger model: numba kernels vs the literal reference, and its behaviour."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import stage_reference as ref
from sim_worlds import box_world

from slam_predict.collect.record import ranger_model_of
from slam_predict.collect.summary import robot_key
from slam_predict.config import config_hash
from slam_predict.sim import SimConfig, Simulator, stage_ranger
from slam_predict.sim import stage_raytrace_kernels as k
from slam_predict.sim.config import LaserOverrides
from slam_predict.world.model import World


def random_world(rng: np.random.Generator) -> World:
    """A small bitmap (border, sparse blobs, sometimes dark pixels on the bottom row) at a
    random origin, so rays cross empty regions, negative coordinates and cell 0."""
    rows, cols = rng.integers(12, 70, size=2)
    occ = np.zeros((rows, cols), dtype=bool)
    if rng.random() < 0.7:
        occ[0, :] = occ[-1, :] = occ[:, 0] = occ[:, -1] = True
    for _ in range(rng.integers(1, 8)):
        r, c = rng.integers(0, rows), rng.integers(0, cols)
        occ[r:r + rng.integers(1, 6), c:c + rng.integers(1, 6)] = True
    occ[-1, rng.integers(0, cols, size=3)] = True
    res = float(rng.choice([0.05, 0.04, 0.1]))
    origin = (float(rng.uniform(-2.0, 2.0)), float(rng.uniform(-2.0, 2.0)))
    return World("random", occ, res, origin=origin)


def reference_grid(world: World, resolution: float, *bodies):
    """The reference grid with robot bodies (x, y, yaw, side) in it (Stage's two layers)."""
    xmin, ymin, xmax, ymax = world.extent
    grid, ppm = ref.stage_grid(world.occupied.tolist(), (xmax - xmin, ymax - ymin),
                               world.origin, resolution)
    for body in bodies:
        grid.map_poly(ref.robot_body(*body, ppm), "robot")
    return grid, ppm


def occupied_cells(grid: stage_ranger.StageGrid) -> set:
    rows, cols = np.nonzero(grid.occupied)
    return set(zip((cols + grid.x0).tolist(), (rows + grid.y0).tolist(), strict=True))


def reference_cells(grid: ref.Grid) -> set:
    cells = set()
    for (sx, sy), regions in grid.superregions.items():
        for (rx, ry), region in regions.items():
            for (cx, cy), models in region["cells"].items():
                if models:
                    cells.add(((sx << ref.SRBITS) + (rx << ref.RBITS) + cx,
                               (sy << ref.SRBITS) + (ry << ref.RBITS) + cy))
    return cells


@pytest.mark.parametrize("seed", range(25))
def test_rect_cutter_matches_reference(seed):
    rng = np.random.default_rng(seed)
    dark = rng.random(tuple(rng.integers(1, 25, size=2))) < rng.uniform(0.1, 0.9)
    got = [tuple(r) for r in k.cut_rects(dark).tolist()]
    assert got == ref.cut_rects(dark.tolist())


def test_rect_cutter_leaves_bottom_row_without_height():
    dark = np.zeros((5, 4), dtype=bool)
    dark[:, 1] = True  # a full-height column
    assert k.cut_rects(dark).tolist() == [[1, 0, 1, 4], [1, 0, 1, 0]]


def random_grid(seed: int):
    """(rng, a random world, a Stage resolution m, its StageGrid), drawn from ``seed``."""
    rng = np.random.default_rng(seed)
    world = random_world(rng)
    res = float(rng.choice([0.025, 0.02, 0.05]))
    return rng, world, res, stage_ranger.StageGrid(world, res)


@pytest.mark.parametrize("seed", range(12))
def test_grid_cells_match_reference(seed):
    _, world, res, grid = random_grid(100 + seed)
    ref_grid, _ = reference_grid(world, res)
    assert occupied_cells(grid) == reference_cells(ref_grid)


@pytest.mark.parametrize("seed", range(30))
def test_ranges_match_reference_exactly(seed):
    rng, world, res, grid = random_grid(200 + seed)
    xmin, ymin, xmax, ymax = world.extent
    for _ in range(3):
        x, y = rng.uniform(xmin - 0.3, xmax + 0.3), rng.uniform(ymin - 0.3, ymax + 0.3)
        yaw = float(rng.uniform(-math.pi, math.pi))
        laser = (x + 0.1 * math.cos(yaw), y + 0.1 * math.sin(yaw), yaw)
        side = float(rng.choice([0.0, 0.3, 0.9]))
        fov, samples = float(rng.uniform(0.5, 2 * math.pi)), int(rng.integers(2, 40))
        range_max = float(rng.uniform(0.2, 8.0))
        before = (x - rng.uniform(0, 0.5), y - rng.uniform(0, 0.5), yaw - 0.2)
        previous = before if rng.random() < 0.5 else None
        got = grid.scan((x, y, yaw), laser, fov, samples, range_max, side,
                        previous_pose=previous)
        bodies = [(x, y, yaw, side)] + ([(*previous, side)] if previous else [])
        ref_grid, ppm = reference_grid(world, res, *(bodies if side else []))
        want = np.array(ref.scan(ref_grid, ppm, laser, fov, samples, range_max),
                        dtype=np.float32)
        np.testing.assert_array_equal(got, want)


def test_axis_rays_match_reference():
    """Beams exactly along the axes (Stage's 1e-12 for heading 0) and their neighbours."""
    world = box_world(4.0, 3.0, res=0.05, wall_px=2)
    grid = stage_ranger.StageGrid(world, 0.025)
    ref_grid, ppm = reference_grid(world, 0.025, (0.33, -0.41, 0.0, 0.3))
    for a in (0.0, math.pi / 2, math.pi, -math.pi / 2, 1e-9, -1e-9, math.pi / 4):
        got = grid.scan((0.33, -0.41, 0.0), (0.33, -0.41, a), 0.0, 1, 10.0, 0.3)
        assert got[0] == np.float32(ref_grid.raytrace(0.33, -0.41, a, 10.0, ppm))


def test_ranges_are_quantised_to_cell_steps():
    """Without region jumps a hit is a whole number of cell steps along the ray's major axis."""
    world = box_world(1.5, 1.5, res=0.05, wall_px=2)  # 60 cells at 0.025: every region populated
    grid = stage_ranger.StageGrid(world, 0.025)
    angles = np.linspace(-math.pi, math.pi, 97)[:-1] + 0.01
    for x, y in ((0.11, 0.07), (-0.23, 0.31), (0.3, -0.2)):
        r = np.array([grid.scan((x, y, 0.0), (x, y, a), 0.0, 1, 5.0, 0.3)[0] for a in angles],
                     dtype=float)
        steps = np.where(np.abs(np.cos(angles)) > np.abs(np.sin(angles)),
                         r * np.abs(np.cos(angles)), r * np.abs(np.sin(angles))) / 0.025
        np.testing.assert_allclose(steps, np.round(steps), atol=2e-4)
        assert np.all(r < 5.0)


def test_walls_move_as_stage_draws_and_reads_them():
    """A 2 m box with 0.1 m walls (interior |x|, |y| < 0.9 m) at 0.025 m cells.

    Vertically the cutter spans rows − 1 pixel units, stretched to 2 m: the bottom wall thins,
    the room moves down. Outlines include the cell at each block's max corner, so walls on the
    −x/−y sides reach one cell into the room, which the ray's truncation toward zero (negative
    cells read one lower) cancels. Net: ±x exact, +y 0.025 m short, −y 0.05 m long.
    """
    world = box_world(2.0, 2.0, res=0.05, wall_px=2)
    grid = stage_ranger.StageGrid(world, 0.025, boundary=False)
    column = np.nonzero(grid.occupied[:, -grid.x0])[0] + grid.y0  # cells at x = 0
    row = np.nonzero(grid.occupied[-grid.y0, :])[0] + grid.x0  # cells at y = 0
    assert column.tolist() == [-40, -38, 35, 40]
    assert row.tolist() == [-40, -36, 36, 40]
    ranges = [grid.scan((0.0, 0.0, 0.0), (0.0, 0.0, a), 0.0, 1, 5.0, 0.3)[0]
              for a in (0.0, math.pi / 2, math.pi, -math.pi / 2)]
    np.testing.assert_allclose(ranges, [0.9, 0.875, 0.9, 0.95], atol=1e-6)


def test_robot_body_is_not_seen():
    world = box_world(3.0, 3.0, res=0.05, wall_px=2)
    grid = stage_ranger.StageGrid(world, 0.025)
    r = grid.scan((0.0, 0.0, 0.3), (0.0, 0.0, 0.3), 2 * math.pi, 73, 10.0, 0.8)
    assert r.min() > 1.0  # the walls, not the 0.8 m body around the laser
    ref_grid, ppm = reference_grid(world, 0.025, (0.0, 0.0, 0.3, 0.8))
    seen = ref_grid.raytrace(0.0, 0.0, 0.3, 10.0, ppm, ignore=())
    assert seen < 0.6  # the reference does hit the body when told not to ignore it


def test_no_hit_reads_range_max():
    world = box_world(6.0, 6.0, res=0.05, wall_px=2)
    grid = stage_ranger.StageGrid(world, 0.025)
    r = grid.scan((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), 2 * math.pi, 50, 1.7, 0.3)
    assert np.all(r == np.float32(1.7))


def test_resolution_choice():
    world = box_world(2.0, 2.0)
    assert stage_ranger.stage_resolution(world, None) == 0.025
    assert stage_ranger.stage_resolution(world, 0.05) == 0.05
    staged = world.replace(provenance={"stage": {"resolution": 0.02}})
    assert stage_ranger.stage_resolution(staged, None) == 0.02


def test_simulator_uses_stage_ranger():
    world = box_world(4.0, 4.0, res=0.05, start=(0.2, -0.3, 0.4),
                      provenance={"stage": {"resolution": 0.04}})
    config = SimConfig(ranger_model="stage", laser=LaserOverrides(noise_std=0.0))
    sim = Simulator(world, config, np.random.default_rng(0))
    assert sim.stage_grid.resolution == 0.04
    pose = sim.true_pose
    laser = sim.laser_world_pose(pose)
    want = stage_ranger.StageGrid(world, 0.04).scan(pose, laser, sim.laser.fov,
                                                    sim.laser.samples, sim.laser.range_max,
                                                    sim.robot.footprint_side)
    np.testing.assert_array_equal(sim.scan_from(pose), want)
    exact = Simulator(world, dataclasses.replace(config, ranger_model="exact"),
                      np.random.default_rng(0))
    assert not np.array_equal(exact.scan_from(pose), want)


def test_config_validation_and_hash():
    with pytest.raises(ValueError, match="exact, stage"):
        SimConfig(ranger_model="gazebo")
    with pytest.raises(ValueError, match="stage_resolution"):
        SimConfig(stage_resolution=0.0)
    base = SimConfig()
    # the default keeps the hash runs recorded before the option existed
    assert config_hash(base) == "7e9890fd4c50"
    assert config_hash(SimConfig(ranger_model="stage")) != config_hash(base)
    assert config_hash(SimConfig(stage_resolution=0.02)) != config_hash(base)


def test_run_records_read_ranger_model():
    assert ranger_model_of({}) == "exact"
    assert ranger_model_of({"ranger_model": "stage"}) == "stage"
    sensor = {"laser": {"fov": 1.0}}
    assert robot_key({"sensor": sensor}) == robot_key({"sensor": sensor,
                                                       "ranger_model": "exact"})
    assert robot_key({"sensor": sensor, "ranger_model": "stage"}).endswith("+stage")


@pytest.mark.parametrize("timing", ["after_move", "before_move"])
def test_simulator_body_in_both_stage_layers(timing):
    """Stage's other layer holds the body one update earlier: the start pose of the step for a
    scan after the move, the start pose of the previous step for a scan before it."""
    world = box_world(12.0, 9.0, res=0.05, start=(-3.0, -2.0, 0.5))
    config = SimConfig(ranger_model="stage", scan_timing=timing,
                       laser=LaserOverrides(noise_std=0.0))
    sim = Simulator(world, config, np.random.default_rng(0))
    grid = sim.stage_grid
    starts = [sim.true_pose.copy()]
    changed = 0
    for _ in range(12):
        state = sim.step(1.0, 0.4)
        starts.append(state.true_pose.copy())  # the next step's start pose
        previous = starts[-2] if timing == "after_move" else starts[max(len(starts) - 3, 0)]
        pose = state.scan_true_pose
        laser = sim.laser_world_pose(pose)
        args = (pose, laser, sim.laser.fov, sim.laser.samples, sim.laser.range_max,
                sim.robot.footprint_side)
        np.testing.assert_array_equal(state.scan, grid.scan(*args, previous_pose=previous))
        changed += int(np.sum(state.scan != grid.scan(*args)))
    assert changed > 0  # the earlier body does change some beams here
