"""The real GMapping's random stream as the differential bench replays it
(bench/gmapping_diff/drand48_rng.py), checked against the C library's own drand48."""
import ctypes
import ctypes.util
import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest

MODULE = Path(__file__).resolve().parents[2] / "bench" / "gmapping_diff" / "drand48_rng.py"


def _module():
    spec = importlib.util.spec_from_file_location("drand48_rng", MODULE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _libc():
    name = ctypes.util.find_library("c")
    if name is None:
        pytest.skip("no C library to compare drand48 with")
    libc = ctypes.CDLL(name)
    libc.drand48.restype = ctypes.c_double
    libc.drand48.argtypes = []
    libc.srand48.argtypes = [ctypes.c_long]
    return libc


def _pf_ran_gaussian(draw):
    """openslam_gmapping utils/stat.cpp, literally (three draws per attempt)."""
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


@pytest.mark.parametrize("seed", [1, 7, 123456789])
def test_stream_equals_libc_drand48(seed):
    libc = _libc()
    libc.srand48(seed)
    _pf_ran_gaussian(libc.drand48)  # sampleGaussian(1, seed) draws once after seeding
    gen = _module().Drand48Generator(seed)
    expected = [libc.drand48() for _ in range(200)]
    assert [gen.random() for _ in range(200)] == expected
    normals = gen.standard_normal((4, 3))
    assert normals.shape == (4, 3)
    np.testing.assert_array_equal(normals.reshape(-1),
                                  [_pf_ran_gaussian(libc.drand48) for _ in range(12)])


def test_gaussians_are_standard_normal():
    gen = _module().Drand48Generator(3)
    v = gen.standard_normal(20000)
    assert abs(v.mean()) < 0.03 and abs(v.std() - 1.0) < 0.03
