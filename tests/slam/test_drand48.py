"""openslam_gmapping's random stream (slam.gmapping.drand48): the numba generator against a slow
pure-Python reference and against the C library's own drand48; how the filter uses it."""
import ctypes
import ctypes.util
import math

import numpy as np
import pytest

from slam_predict.slam.gmapping.drand48 import Drand48Generator, noise_generator
from slam_predict.slam.gmapping.motion import draw_from_motion, noise_stds, odometry_step


class SlowDrand48:
    """Obviously-correct reference: the 48-bit LCG on Python ints, pf_ran_gaussian literally,
    seeded as sampleGaussian(1, seed) seeds it (no srand48 for seed 0)."""

    def __init__(self, seed: int):
        self.x = 0x1234ABCD330E if seed == 0 else ((seed & 0xFFFFFFFF) << 16) | 0x330E
        self.gaussian()

    def drand48(self) -> float:
        self.x = (0x5DEECE66D * self.x + 0xB) % (1 << 48)
        return self.x / 2.0 ** 48

    def gaussian(self) -> float:
        return pf_ran_gaussian(self.drand48)


def pf_ran_gaussian(draw) -> float:
    """openslam_gmapping utils/stat.cpp's polar method: three draws per attempt, the second only
    tested for zero."""
    while True:
        r = draw()
        while r == 0.0:
            r = draw()
        x1 = 2.0 * r - 1.0
        r = draw()
        while r == 0.0:
            r = draw()
        x2 = 2.0 * draw() - 1.0
        w = x1 * x1 + x2 * x2
        if not (w > 1.0 or w == 0.0):
            return x2 * math.sqrt(-2.0 * math.log(w) / w)


def _libc():
    name = ctypes.util.find_library("c")
    if name is None:
        pytest.skip("no C library to compare drand48 with")
    libc = ctypes.CDLL(name)
    libc.drand48.restype = ctypes.c_double
    libc.drand48.argtypes = []
    libc.srand48.argtypes = [ctypes.c_long]
    return libc


@pytest.mark.parametrize("seed", [0, 1, 7, 123456789, 2 ** 32 - 1])
def test_stream_equals_the_slow_reference(seed):
    fast, slow = Drand48Generator(seed), SlowDrand48(seed)
    np.testing.assert_array_equal(fast.standard_normal((50, 3)).reshape(-1),
                                  [slow.gaussian() for _ in range(150)])
    assert [fast.random() for _ in range(20)] == [slow.drand48() for _ in range(20)]
    np.testing.assert_array_equal(fast.random(7), [slow.drand48() for _ in range(7)])
    assert fast.standard_normal(4).tolist() == [slow.gaussian() for _ in range(4)]


@pytest.mark.parametrize("seed", [1, 7, 123456789])
def test_stream_equals_libc_drand48(seed):
    libc = _libc()
    libc.srand48(seed)
    pf_ran_gaussian(libc.drand48)  # sampleGaussian(1, seed) draws once after seeding
    gen = Drand48Generator(seed)
    assert [gen.random() for _ in range(200)] == [libc.drand48() for _ in range(200)]
    normals = gen.standard_normal((4, 3))
    assert normals.shape == (4, 3)
    np.testing.assert_array_equal(normals.reshape(-1),
                                  [pf_ran_gaussian(libc.drand48) for _ in range(12)])


def test_bad_seeds_are_refused():
    for seed in (-1, 2 ** 32):
        with pytest.raises(ValueError, match="drand48 seed"):
            Drand48Generator(seed)


def test_gaussians_are_standard_normal():
    v = Drand48Generator(3).standard_normal(20000)
    assert abs(v.mean()) < 0.03 and abs(v.std() - 1.0) < 0.03


def test_motion_draws_particle_by_particle_skipping_zero_sigmas():
    """Upstream drawFromMotion: per particle sampleGaussian(σx), (σy), (σθ); σ = 0 draws
    nothing. A pure rotation in place has σθ > 0 and σx = σy = str·|dθ|: zero with str = 0."""
    poses = np.array([[0.0, 0.0, 0.0], [1.0, 2.0, 0.5], [-1.0, 0.5, -2.0]])
    for p_new, str_ in (([0.3, 0.1, 0.2], 0.1), ([0.0, 0.0, 0.4], 0.0)):
        stds = noise_stds(odometry_step(p_new, [0, 0, 0]), 0.1, 0.2, str_, 0.2)
        slow = SlowDrand48(5)
        expected = poses.copy()
        for i in range(3):
            step = odometry_step(p_new, [0, 0, 0])
            step += [s * slow.gaussian() if s > 0 else 0.0 for s in stds]
            c, s = math.cos(poses[i, 2]), math.sin(poses[i, 2])
            expected[i, :2] += (c * step[0] - s * step[1], s * step[0] + c * step[1])
            expected[i, 2] = math.remainder(poses[i, 2] + step[2], 2 * math.pi)
        got = draw_from_motion(poses, p_new, [0, 0, 0], 0.1, 0.2, str_, 0.2,
                               Drand48Generator(5))
        np.testing.assert_allclose(got, expected, atol=1e-12)


def test_noise_generator_follows_the_params():
    rng = np.random.default_rng(4)
    gen, seed = noise_generator("numpy", None, rng)
    assert gen is rng and seed is None
    gen, seed = noise_generator("drand48", 9, np.random.default_rng(4))
    assert seed == 9 and gen.random() == Drand48Generator(9).random()
    gen, seed = noise_generator("drand48", None, np.random.default_rng(4))
    assert seed == int(np.random.default_rng(4).integers(1, 2 ** 31 - 1))
    assert gen.random() == Drand48Generator(seed).random()
    with pytest.raises(ValueError, match="random_stream"):
        noise_generator("pcg64", None, rng)
