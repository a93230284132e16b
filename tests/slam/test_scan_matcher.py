"""Scan matcher kernels: score/likelihood vs a slow reference, hill climbing recovers offsets."""
import math

import numpy as np
import pytest
from slam_synthetic import cast

from slam_predict.slam.gmapping import kernels
from slam_predict.slam.gmapping.maps import Geometry, ParticleMap, PatchPool
from slam_predict.slam.gmapping.params import FREE_CELL_RATIO

ANGLES = np.radians(np.arange(-90.0, 90.0, 1.0))
CA, SA = np.cos(ANGLES), np.sin(ANGLES)
TRUE_POSES = [(-3.5, -2.0, 0.2), (-1.0, -2.5, 1.0), (3.0, -2.0, 2.0), (3.5, 2.5, -2.5),
              (-1.0, 0.5, 0.0)]


def survey_poses(n=40, seed=0):
    """Random laser poses in the room's free space (outside the pillar)."""
    rng = np.random.default_rng(seed)
    poses = [(rng.uniform(-4.5, 4.5), rng.uniform(-3.5, 3.5), rng.uniform(-3, 3)) for _ in range(n)]
    return [p for p in poses if not (0.8 < p[0] < 2.2 and 0.8 < p[1] < 2.2)]


def built_map(poses=TRUE_POSES, max_range=30.0):
    pool = PatchPool(8)
    pmap = ParticleMap(pool, Geometry.particle_map(-100, -100, 100, 100, 0.05))
    for pose in poses:
        pmap.register(pose, cast(pose, ANGLES), CA, SA, max_range, max_range)
    return pmap


def geo_args(pmap):
    g = pmap.geometry
    return (pmap.table, g.sx2, g.sy2, g.cx, g.cy, g.delta, pmap.pool.acc, pmap.pool.hits)


def slow_best(pmap, hx, hy, r, lx, ly, dx, dy, back, bug, k=1):
    """Reference of the window search, written from the upstream description."""
    g = pmap.geometry
    ix, iy = g.world_to_cell(hx, hy)
    if bug:
        fx, fy = g.world_to_cell((lx + (r - back) * dx) - hx, (ly + (r - back) * dy) - hy)
    else:
        fx, fy = np.subtract(g.world_to_cell(hx - back * dx, hy - back * dy), (ix, iy))
    best = None
    for xx in range(-k, k + 1):
        for yy in range(-k, k + 1):
            n, mx, my = pmap.cell(ix + xx, iy + yy)
            nf, _, _ = pmap.cell(ix + xx + fx, iy + yy + fy)
            if n > 0 and nf == 0:
                d2 = (hx - mx) ** 2 + (hy - my) ** 2
                best = d2 if best is None or d2 < best else best
    return best


def slow_score_and_likelihood(pmap, pose, ranges, usable, sigma=0.05, lsigma=0.075, bug=True):
    x, y, th = pose
    delta = pmap.geometry.delta
    s = l_sum = 0.0
    s_only = 0.0
    for r, a in zip(ranges, ANGLES, strict=False):
        if r > usable:
            continue
        dx, dy = math.cos(th + a), math.sin(th + a)
        hx, hy = x + r * dx, y + r * dy
        best = slow_best(pmap, hx, hy, r, x, y, dx, dy, delta * FREE_CELL_RATIO, bug)
        l_sum += -best / lsigma if best is not None else -0.5 / lsigma
        if best is not None:
            s += math.exp(-best / sigma)
        if r != 0.0:
            back = delta * delta * FREE_CELL_RATIO if bug else delta * FREE_CELL_RATIO
            b2 = slow_best(pmap, hx, hy, r, x, y, dx, dy, back, bug)
            if b2 is not None:
                s_only += math.exp(-b2 / sigma)
    return s_only, s, l_sum


@pytest.mark.parametrize("bug", [True, False])
def test_score_and_likelihood_match_a_slow_reference(bug):
    pmap = built_map()
    rng = np.random.default_rng(3)
    for _ in range(6):
        pose = (np.array(TRUE_POSES[rng.integers(len(TRUE_POSES))])
                + rng.normal(0, [0.05, 0.05, 0.03]))
        ranges = cast(TRUE_POSES[0], ANGLES)
        ranges[::17] = 0.0
        ranges[::23] = 31.0
        ref_score, ref_s, ref_l = slow_score_and_likelihood(pmap, pose, ranges, 30.0, bug=bug)
        got = kernels.score(*geo_args(pmap), *pose, ranges, CA, SA, 30.0, 0.05, 1, 0, bug)
        s, lik, _ = kernels.likelihood_and_score(*geo_args(pmap), *pose, ranges, CA, SA, 30.0,
                                                 0.05, 0.075, 1, 0, bug)
        assert got == pytest.approx(ref_score, rel=1e-9)
        assert s == pytest.approx(ref_s, rel=1e-9)
        assert lik == pytest.approx(ref_l, rel=1e-9)


def test_lskip_uses_every_lskip_plus_one_th_beam():
    pmap = built_map()
    ranges = cast(TRUE_POSES[1], ANGLES)
    full = kernels.score(*geo_args(pmap), *TRUE_POSES[1], ranges, CA, SA, 30.0, 0.05, 1, 0, True)
    only = ranges.copy()
    only[0::2] = 31.0  # lskip=1 uses beams 1, 3, 5, ...
    half = kernels.score(*geo_args(pmap), *TRUE_POSES[1], only, CA, SA, 30.0, 0.05, 1, 0, True)
    skip = kernels.score(*geo_args(pmap), *TRUE_POSES[1], ranges, CA, SA, 30.0, 0.05, 1, 1, True)
    assert skip == pytest.approx(half) and 0 < skip < full


@pytest.mark.parametrize("bug", [True, False])
@pytest.mark.parametrize("offset", [(0.08, -0.06, 0.04), (-0.1, 0.05, -0.05), (0.03, 0.1, 0.0)])
def test_hill_climbing_recovers_a_known_offset(bug, offset):
    pmap = built_map(survey_poses())  # many scans: cell means settle on the walls
    truth = np.array([0.0, -1.0, 0.6])
    ranges = cast(truth, ANGLES)
    start = truth + np.array(offset)
    x, y, th, best = kernels.optimize(*geo_args(pmap), *start, ranges, CA, SA, 30.0, 0.05, 1, 0,
                                      bug, 0.05, 0.05, 5)
    assert math.hypot(x - truth[0], y - truth[1]) <= 0.02
    assert abs(th - truth[2]) <= math.radians(0.5)
    assert best == pytest.approx(kernels.score(*geo_args(pmap), x, y, th, ranges, CA, SA, 30.0,
                                               0.05, 1, 0, bug))


def test_optimize_on_an_empty_map_stays_put():
    pmap = ParticleMap(PatchPool(2), Geometry.particle_map(-100, -100, 100, 100, 0.05))
    ranges = cast((0, 0, 0), ANGLES)
    out = kernels.match_particle(*geo_args(pmap), 0.1, 0.2, 0.3, ranges, CA, SA, 30.0, 0.05,
                                 0.075, 1, 0, True, 0.05, 0.05, 5, 0.0)
    assert out[:4] == (0.1, 0.2, 0.3, 0.0)
    assert out[4] == pytest.approx(len(ranges) * -0.5 / 0.075)


def test_c_round_rounds_halves_away_from_zero():
    for v, want in [(0.5, 1), (1.5, 2), (2.5, 3), (-0.5, -1), (-2.5, -3), (0.49, 0), (-0.51, -1)]:
        assert kernels.c_round(v) == want


def slow_optimize(args, start, ranges, bug, lstep=0.05, astep=0.05, iterations=5):
    """ScanMatcher::optimize written plainly: every move scored with kernels.score."""
    def score(pose):
        return kernels.score(*args, *pose, ranges, CA, SA, 30.0, 0.05, 1, 0, bug)
    pose, current, best = tuple(start), score(start), -1.0
    ldelta, adelta, refinement = lstep, astep, 0
    while True:
        if best >= current:
            refinement, ldelta, adelta = refinement + 1, ldelta / 2, adelta / 2
        best, chosen = current, pose
        x, y, th = pose
        for move in [(x + ldelta, y, th), (x - ldelta, y, th), (x, y - ldelta, th),
                     (x, y + ldelta, th), (x, y, th + adelta), (x, y, th - adelta)]:
            local = score(move)
            if local > current:
                current, chosen = local, move
        pose = chosen
        if not (current > best or refinement < iterations):
            return (*pose, best)


@pytest.mark.parametrize("bug", [True, False])
def test_optimize_equals_the_plain_hill_climbing(bug):
    """The kernel (which skips re-scoring the pose it just left) gives exactly the plain result."""
    pmap = built_map(survey_poses())
    rng = np.random.default_rng(3)
    for _ in range(12):
        truth = np.array([rng.uniform(-3.0, 3.0), rng.uniform(-2.5, 0.5), rng.uniform(-3, 3)])
        start = truth + rng.normal(0.0, [0.08, 0.08, 0.05])
        ranges = cast(truth, ANGLES)
        got = kernels.optimize(*geo_args(pmap), *start, ranges, CA, SA, 30.0, 0.05, 1, 0, bug,
                               0.05, 0.05, 5)
        assert got == slow_optimize(geo_args(pmap), start, ranges, bug)


def plain_best_d2(pmap, hx, hy, ix, iy, ofx, ofy, k):
    """The window search cell by cell through ParticleMap.cell, with the kernel's arithmetic."""
    best = -1.0
    for xx in range(-k, k + 1):
        for yy in range(-k, k + 1):
            n, _, _ = pmap.cell(ix + xx, iy + yy)
            if n <= 0 or pmap.cell(ix + xx + ofx, iy + yy + ofy)[0] > 0:
                continue
            pid = pmap.table[(ix + xx) >> 5, (iy + yy) >> 5]
            s = kernels.slot(ix + xx, iy + yy)
            mx = hx - (1.0 / n) * float(pmap.pool.acc[pid, s, 0])
            my = hy - (1.0 / n) * float(pmap.pool.acc[pid, s, 1])
            if best < 0.0 or mx * mx + my * my < best:
                best = mx * mx + my * my
    return best


@pytest.mark.parametrize("k", [0, 1, 2])
def test_window_search_equals_the_plain_one_inside_and_across_patches(k):
    """Windows inside one patch take the kernel's one-lookup path; across patch edges the
    general one: both give exactly the plain cell-by-cell result."""
    pmap = built_map(survey_poses())
    rng = np.random.default_rng(5)
    g = pmap.geometry
    inside = across = 0
    for pose in survey_poses(12, seed=1):
        ranges = cast(pose, ANGLES)
        for r, a in zip(ranges, ANGLES, strict=True):
            hx, hy = pose[0] + r * math.cos(pose[2] + a), pose[1] + r * math.sin(pose[2] + a)
            ix, iy = g.world_to_cell(hx, hy)
            ofx, ofy = (int(v) for v in rng.integers(-2, 3, size=2))
            got = kernels._best_d2(pmap.table, pmap.pool.acc, pmap.pool.hits, hx, hy, ix, iy,
                                   ofx, ofy, k)
            assert got == plain_best_d2(pmap, hx, hy, ix, iy, ofx, ofy, k)
            one = (ix - k) >> 5 == (ix + k) >> 5 and (iy - k) >> 5 == (iy + k) >> 5
            inside += one
            across += not one
    assert inside > 100 and (across > 10 or k == 0)   # a 1-cell window never crosses


@pytest.mark.parametrize("k", [0, 1, 2])
def test_window_means_give_the_plain_window_search(k):
    """The cell means the cached score keeps per beam give the plain window search's best
    squared distance (none kept where it finds no cell)."""
    pmap = built_map(survey_poses())
    rng = np.random.default_rng(7)
    g = pmap.geometry
    means = np.empty(((2 * k + 1) ** 2, 2))
    found = 0
    for pose in survey_poses(8, seed=2):
        ranges = cast(pose, ANGLES)
        for r, a in zip(ranges, ANGLES, strict=True):
            hx, hy = pose[0] + r * math.cos(pose[2] + a), pose[1] + r * math.sin(pose[2] + a)
            ix, iy = g.world_to_cell(hx + rng.normal(0, 0.05), hy + rng.normal(0, 0.05))
            ofx, ofy = (int(v) for v in rng.integers(-2, 3, size=2))
            n = kernels._window_means(pmap.table, pmap.pool.acc, pmap.pool.hits, ix, iy, ofx,
                                      ofy, k, means)
            want = plain_best_d2(pmap, hx, hy, ix, iy, ofx, ofy, k)
            got = min(((hx - mx) * (hx - mx) + (hy - my) * (hy - my) for mx, my in means[:n]),
                      default=-1.0)
            assert got == want
            found += n > 0
    assert found > 100


@pytest.mark.parametrize("bug", [True, False])
def test_cached_scores_equal_the_plain_scores(bug):
    """One cache over a run of poses (repeats, sub-cell moves, jumps, turns) gives every
    pose exactly kernels.score's value."""
    pmap = built_map(survey_poses())
    rng = np.random.default_rng(11)
    nb = len(ANGLES)
    keys = np.full((nb, 4), -(1 << 62), np.int64)
    means, counts = np.empty((nb, 9, 2)), np.zeros(nb, np.int64)
    pose = np.array([-1.0, -1.0, 0.3])
    ranges = cast(pose, ANGLES)
    for step in range(60):
        kind = step % 4
        if kind == 1:
            pose = pose + rng.normal(0.0, [0.01, 0.01, 0.003])
        elif kind == 2:
            pose = pose + rng.normal(0.0, [0.2, 0.2, 0.1])
        elif kind == 3 and step % 8 == 3:
            pose = np.array([rng.uniform(-3, 3), rng.uniform(-2.5, 0.5), rng.uniform(-3, 3)])
        args = (*geo_args(pmap), *pose, ranges, CA, SA, 30.0, 0.05, 1, 0, bug)
        assert kernels.score_cached(*args, keys, means, counts) == kernels.score(*args)
