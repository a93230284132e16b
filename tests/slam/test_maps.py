"""Copy-on-write patch maps: sharing, private copies before writes, growth, pool reuse."""
import numpy as np
import pytest
from slam_scan import ANGLES, CA, SA, scan_of

from slam_predict.slam.gmapping.maps import Geometry, ParticleMap, PatchPool


def fresh(capacity=4):
    return ParticleMap(PatchPool(capacity), Geometry.particle_map(-100, -100, 100, 100, 0.05))


def test_initial_geometry_is_gmappings():
    g = Geometry.particle_map(-100, -100, 100, 100, 0.05)
    assert (g.nx, g.ny, g.sx2, g.sy2, g.size) == (125, 125, 2000, 2000, (4000, 4000))
    assert g.world_to_cell(0.0, 0.0) == (2000, 2000)
    assert g.world_to_cell(0.025, -0.025) == (2001, 1999)  # C round: halves away from zero
    assert g.cell_to_world(0, 0) == (-100.0, -100.0)


def test_shared_patch_is_copied_before_it_is_written():
    a = fresh()
    pose = (0.0, 0.0, 0.0)
    a.register(pose, scan_of(pose), CA, SA, 30.0, 30.0)
    b = a.clone()
    assert np.array_equal(a.table, b.table)
    used = a.table[a.table >= 0]
    assert np.all(a.pool.ref[used] == 2)
    before = a.pool.hits[used].copy()
    pose2 = (0.5, 0.2, 0.3)
    taken = b.register(pose2, scan_of(pose2), CA, SA, 30.0, 30.0)
    assert taken > 0
    assert np.array_equal(a.pool.hits[used], before)          # a's patches untouched
    changed = (a.table != b.table) & (a.table >= 0)
    assert changed.any()
    assert np.all(a.pool.ref[a.table[changed]] == 1)          # now private to a
    total_a = sum(a.cell(ix, iy)[0] for ix in range(1800, 2200) for iy in range(1850, 2150))
    total_b = sum(b.cell(ix, iy)[0] for ix in range(1800, 2200) for iy in range(1850, 2150))
    assert total_b > total_a > 0


def test_private_patches_are_written_in_place_and_released_patches_reused():
    a = fresh()
    pose = (0.0, 0.0, 0.0)
    first = a.register(pose, scan_of(pose), CA, SA, 30.0, 30.0)
    assert first > 0 and a.register(pose, scan_of(pose), CA, SA, 30.0, 30.0) == 0
    in_use = a.pool.in_use
    b = a.clone()
    a.release()
    assert a.pool.in_use == in_use                            # b still holds them
    b.release()
    assert b.pool.in_use == 0


def test_pool_grows_when_needed_and_keeps_contents():
    a = fresh(capacity=1)
    pose = (0.0, 0.0, 0.0)
    a.register(pose, scan_of(pose), CA, SA, 30.0, 30.0)
    assert a.pool.capacity >= a.allocated_patches > 1
    n, mx, my = a.cell(*a.geometry.world_to_cell(5.0, 0.0))
    assert n == 1 and mx == pytest.approx(5.0, abs=1e-5)


def test_hits_accumulate_endpoint_means():
    a = fresh()
    ranges = np.full(len(ANGLES), 31.0)
    ranges[90] = 2.0                                          # beam at 0 rad
    for x in (0.0, 0.01, 0.02):
        a.register((x, 0.0, 0.0), ranges, CA, SA, 30.0, 30.0)
    n, mx, my = a.cell(*a.geometry.world_to_cell(2.01, 0.0))
    assert n == 3 and mx == pytest.approx(2.01, abs=1e-5) and my == pytest.approx(0.0, abs=1e-6)
    assert a.allocated_patches == 1                           # beams beyond range register nothing


def test_map_grows_by_the_enlarge_step_and_keeps_cells():
    a = ParticleMap(PatchPool(4), Geometry.particle_map(-5, -5, 5, 5, 0.05))
    assert a.geometry.size == (192, 192)                      # 200 cells floored to patches
    ranges = np.full(len(ANGLES), 31.0)
    ranges[90] = 3.0                                          # beam at 0 rad
    a.register((0.0, 0.0, 0.0), ranges, CA, SA, 30.0, 30.0)
    assert a.geometry.size == (192, 192)
    cell_before = a.cell(*a.geometry.world_to_cell(3.0, 0.0))
    assert cell_before[0] == 1
    ranges[90] = 6.0
    a.register((4.0, 3.0, 0.0), ranges, CA, SA, 30.0, 30.0)  # hits x = 10 m, outside the map
    xmin, ymin = a.geometry.cell_to_world(0, 0)
    xmax, ymax = a.geometry.cell_to_world(a.geometry.size[0] - 1, a.geometry.size[1] - 1)
    assert 20.0 <= xmax <= 20.0 + 0.05 * 32                   # enlargeStep past the hit
    assert (xmin, ymin, ymax) == pytest.approx((-4.8, -4.8, 4.75))
    assert a.cell(*a.geometry.world_to_cell(3.0, 0.0)) == cell_before
    assert a.cell(*a.geometry.world_to_cell(10.0, 3.0))[0] == 1
    assert a.table.shape == (a.geometry.nx, a.geometry.ny)
