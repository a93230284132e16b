"""numpy's maths pinned at the AVX2 level when slam_predict is imported first."""
import os
import platform
import subprocess
import sys

import pytest

from slam_predict import NUMPY_CPU_PIN

PROBE = ("import slam_predict, numpy\n"
         "try:\n"
         "    from numpy._core._multiarray_umath import __cpu_dispatch__ as d, "
         "__cpu_features__ as f\n"
         "except ImportError:\n"
         "    from numpy.core._multiarray_umath import __cpu_dispatch__ as d, "
         "__cpu_features__ as f\n"
         "import os\n"
         "print(os.environ.get('NPY_DISABLE_CPU_FEATURES'))\n"
         "print(' '.join(k for k in d if f.get(k)))\n")


def probe(extra_env: dict) -> list[str]:
    env = {k: v for k, v in os.environ.items() if k != "NPY_DISABLE_CPU_FEATURES"}
    done = subprocess.run([sys.executable, "-c", PROBE], env={**env, **extra_env},
                          capture_output=True, text=True, check=True)
    return done.stdout.splitlines()


@pytest.mark.skipif(platform.machine() not in ("x86_64", "AMD64"), reason="x86 feature names")
def test_numpy_dispatches_no_avx512_routine_after_import():
    setting, active = probe({})
    assert setting == NUMPY_CPU_PIN
    assert not [name for name in active.split() if "AVX512" in name or name == "X86_V4"]


def test_a_value_the_user_set_wins():
    assert probe({"NPY_DISABLE_CPU_FEATURES": ""})[0] == ""
