"""Shared synthetic-scan helpers for the SLAM tests."""
import numpy as np
from slam_synthetic import cast

ANGLES = np.radians(np.arange(-90.0, 90.0, 1.0))
CA, SA = np.cos(ANGLES), np.sin(ANGLES)


def scan_of(pose, angles=ANGLES):
    """Ranges (m) of the synthetic room seen from laser pose ``pose``."""
    return cast(pose, angles)
