"""Sight lines of a plan (features/sightline.py) against a slow reference and known answers."""
from __future__ import annotations

import math

import numpy as np
import pytest

from slam_predict.features.sightline import (
    BLIND_FLOOR,
    CURVE_RANGES_M,
    SightlineConfig,
    blind_curve,
    blind_fraction,
    curve_columns,
    sample_points,
    sight_lines,
    sightline_features,
)
from slam_predict.sim.raycast import GridFrame

from .plans import Plan, corridor_with_rooms


def marched_distance(occupied: np.ndarray, frame: GridFrame, x: float, y: float,
                     angle: float, max_range: float, step: float = 0.002) -> float:
    """Slow reference: walk along the ray in ``step`` m until a cell is occupied (or outside)."""
    rows, cols = occupied.shape
    for k in range(1, int(max_range / step) + 1):
        t = k * step
        col = math.floor((x + t * math.cos(angle) - frame.x_left) / frame.resolution)
        row = math.floor((frame.y_top - (y + t * math.sin(angle))) / frame.resolution)
        if not (0 <= row < rows and 0 <= col < cols) or occupied[row, col]:
            return t
    return math.inf


def test_sight_lines_match_a_marching_reference():
    world = corridor_with_rooms(3).world()
    config = SightlineConfig(spacing_m=2.0, beams=24, max_range_m=12.0)
    distances = sight_lines(world, config)
    rows, cols = sample_points(world.occupied, world.resolution, config)
    frame = GridFrame.of_world(world)
    assert distances.shape == (rows.size, 24) and rows.size >= 5
    for i, (r, c) in enumerate(zip(rows, cols, strict=True)):
        x = frame.x_left + (c + 0.5) * frame.resolution
        y = frame.y_top - (r + 0.5) * frame.resolution
        for b in range(24):
            ref = marched_distance(world.occupied, frame, x, y, b * 2 * math.pi / 24, 12.0)
            if math.isinf(ref):
                assert math.isinf(distances[i, b])
            else:
                assert distances[i, b] == pytest.approx(ref, abs=0.005)


def test_sample_points_keep_their_clearance_and_spacing():
    plan = Plan(12.0, 8.0, 0.05).room("hall", (1.0, 1.0, 11.0, 7.0))   # 10 × 6 m inside
    world = plan.world()
    rows, cols = sample_points(world.occupied, 0.05, SightlineConfig(spacing_m=1.0,
                                                                     clearance_m=0.3))
    # 1 m squares whose centre pixel is at least 0.3 m inside the hall: 10 × 6 of them
    assert rows.size == 60
    assert np.all(np.diff(np.unique(cols)) == 20) and np.all(np.diff(np.unique(rows)) == 20)


def test_a_room_s_curve_has_known_ends():
    """A 10 × 6 m hall: every sight line hits a wall within the hall's diagonal (11.7 m);
    within 1 m only those of points near a wall do; the curve never rises."""
    world = Plan(12.0, 8.0, 0.05).room("hall", (1.0, 1.0, 11.0, 7.0)).world()
    features = sightline_features(world)
    assert list(features) == [*curve_columns(), "sightline_isotropy", "floor_elongation"]
    assert features["floor_elongation"] == pytest.approx(10.0 / 6.0)     # 10 × 6 squares
    curve = np.array([features[c] for c in curve_columns()])
    ranges = np.array(CURVE_RANGES_M)
    assert 0.5 < curve[0] < 1.0
    assert np.all(curve[ranges >= 11.7] == 0.0) and curve[ranges < 3.0].min() > 0.0
    assert np.all(np.diff(curve) <= 0.0)


def test_blind_curve_counts_sight_lines_beyond_each_range():
    distances = np.array([[1.0, 2.0, np.inf, 5.0]])
    np.testing.assert_allclose(blind_curve(distances, (0.5, 1.0, 2.5, 5.0, 50.0)),
                               [1.0, 0.75, 0.5, 0.25, 0.25])
    np.testing.assert_allclose(blind_curve(np.zeros((0, 4)), (1.0, 2.0)), [1.0, 1.0])


def test_blind_fraction_interpolates_the_curve_log_log():
    curve = np.array([0.5 ** r for r in CURVE_RANGES_M])          # log-linear in r
    for k, r in enumerate(CURVE_RANGES_M):
        expected = max(curve[k], BLIND_FLOOR)
        assert blind_fraction(curve, r) == pytest.approx(expected, rel=1e-12)
    a, b = CURVE_RANGES_M[3], CURVE_RANGES_M[4]
    middle = math.sqrt(a * b)                                      # half-way in log r
    assert blind_fraction(curve, middle) == pytest.approx(
        math.sqrt(curve[3] * curve[4]), rel=1e-12)
    assert blind_fraction(curve, 0.1) == blind_fraction(curve, CURVE_RANGES_M[0])
    assert blind_fraction(curve, 500.0) == pytest.approx(BLIND_FLOOR, rel=1e-12)
    columns = dict(zip(curve_columns(), curve, strict=True))
    assert blind_fraction(columns, 7.3) == blind_fraction(curve, 7.3)
