"""slam_predict: predict GMapping's localization error in a building from its floor plan.

The library never imports rospy; the ROS layer lives in :mod:`slam_predict.ros`.
"""
import logging
import os

__version__ = "0.1.0"

# Same seed, same run on every x86 host: numpy's exp, log and arctan2 give other last bits with
# its AVX-512 routines than with its AVX2 ones, and a long closed-loop run grows that into another
# exploration. Keep numpy at the AVX2 level (it reads this when first imported; a value the user
# set, even empty, wins). docs/architecture.md "Same seed, same run".
NUMPY_CPU_PIN = "X86_V4 AVX512_ICL AVX512_SPR"
os.environ.setdefault("NPY_DISABLE_CPU_FEATURES", NUMPY_CPU_PIN)

logging.getLogger(__name__).addHandler(logging.NullHandler())
