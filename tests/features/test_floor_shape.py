"""Floor elongation (features/floor_shape.py) against a slow reference and known plans."""
from __future__ import annotations

import math

import numpy as np
import pytest

from slam_predict.features.floor_shape import ELONGATION_COLUMN, elongation, floor_covariance
from slam_predict.features.sightline import SightlineConfig, sightline_features

from .plans import Plan


def reference_covariance(x_m, y_m, spacing_m: float, sub: int = 40) -> np.ndarray:
    """Slow reference: each point's square replaced by sub × sub sample points at the centres
    of its sub-squares, their covariance accumulated in a loop."""
    offsets = (np.arange(sub) + 0.5) / sub * spacing_m - spacing_m / 2
    samples = [(x + dx, y + dy) for x, y in zip(x_m, y_m, strict=True)
               for dx in offsets for dy in offsets]
    mean = np.mean(samples, axis=0)
    cov = np.zeros((2, 2))
    for p in samples:
        d = np.asarray(p) - mean
        cov += np.outer(d, d)
    return cov / len(samples)


def test_covariance_matches_the_reference_on_random_points():
    rng = np.random.default_rng(5)
    x, y = rng.uniform(0, 20, 25), rng.uniform(0, 5, 25)
    got = floor_covariance(x, y, 1.0)
    # the sub-sampled square's variance is (1 - 1/sub²) / 12 of the continuous one's
    assert got == pytest.approx(reference_covariance(x, y, 1.0), abs=1e-3)


def test_a_rectangle_of_squares_has_its_aspect_ratio_in_any_orientation():
    cols, rows = np.meshgrid(np.arange(40), np.arange(4))
    x, y = cols.ravel() + 0.5, rows.ravel() + 0.5
    assert elongation(x, y, 1.0) == pytest.approx(10.0, rel=1e-12)
    angle = 0.7
    xr = math.cos(angle) * x - math.sin(angle) * y
    yr = math.sin(angle) * x + math.cos(angle) * y
    assert elongation(xr, yr, 1.0) == pytest.approx(10.0, rel=1e-9)
    assert elongation([3.0], [4.0], 1.0) == pytest.approx(1.0)      # one square


def test_no_points_are_refused():
    with pytest.raises(ValueError):
        floor_covariance(np.zeros(0), np.zeros(0), 1.0)


def test_a_corridor_plan_is_long_and_a_hall_is_not():
    """Standable 1 m squares: the corridor's are 60 × 2 of them, the hall's 10 × 10."""
    config = SightlineConfig(spacing_m=1.0, beams=36)
    hall = Plan(12.0, 12.0, 0.05).room("hall", (1.0, 1.0, 11.0, 11.0)).world()
    corridor = Plan(62.0, 4.0, 0.05).room("corridor", (1.0, 1.0, 61.0, 3.0)).world()
    assert sightline_features(hall, config)[ELONGATION_COLUMN] == pytest.approx(1.0)
    assert sightline_features(corridor, config)[ELONGATION_COLUMN] == pytest.approx(30.0)
