"""Scan isotropy (features/scan_conditioning.py) against a slow reference and known plans."""
from __future__ import annotations

import math

import numpy as np
import pytest

from slam_predict.features.scan_conditioning import (
    ISOTROPY_COLUMN,
    mean_isotropy,
    scan_isotropy,
)
from slam_predict.features.sightline import SightlineConfig, sight_lines, sightline_features

from .plans import Plan


def reference_isotropy(row: np.ndarray, range_m: float, max_gap_m: float) -> float:
    """Slow reference: hit points beam by beam, a normal per neighbouring pair on one wall,
    the 2 × 2 information matrix summed in a loop, eigenvalues by numpy."""
    beams = row.size
    points = [None if not row[k] <= range_m else
              (row[k] * math.cos(2 * math.pi * k / beams),
               row[k] * math.sin(2 * math.pi * k / beams)) for k in range(beams)]
    info = np.zeros((2, 2))
    for k in range(beams):
        p, q = points[k], points[(k + 1) % beams]
        if p is None or q is None:
            continue
        gap = math.dist(p, q)
        if not 1e-9 < gap < max_gap_m:
            continue
        normal = np.array([-(q[1] - p[1]), q[0] - p[0]]) / gap
        info += np.outer(normal, normal)
    low, high = np.linalg.eigvalsh(info)
    return 0.0 if high <= 0 else low / high


def test_scan_isotropy_matches_the_reference_on_random_scans():
    rng = np.random.default_rng(3)
    rows = rng.uniform(0.5, 12.0, size=(30, 90))
    rows[rng.random(rows.shape) < 0.2] = np.inf                  # no-hit beams
    rows[:5] = 4.0 + rng.normal(0.0, 0.05, size=(5, 90))         # circles: round walls
    rows[5] = np.inf                                             # a scan that sees nothing
    got = scan_isotropy(rows, range_m=8.0, max_gap_m=1.0)
    want = [reference_isotropy(r, 8.0, 1.0) for r in rows]
    assert got == pytest.approx(want, abs=1e-9)
    assert got[5] == 0.0 and np.all(got[:5] > 0.8)


def test_a_corridor_scan_is_degenerate_and_a_room_scan_is_not():
    beams = 360
    angles = np.arange(beams) * 2 * math.pi / beams
    with np.errstate(divide="ignore"):
        corridor = np.abs(1.0 / np.sin(angles))          # walls at y = ±1 m, no ends
        square = np.minimum(np.abs(3.0 / np.cos(angles)), np.abs(3.0 / np.sin(angles)))
    iso = scan_isotropy(np.vstack([corridor, square]), range_m=10.0)
    assert iso[0] == pytest.approx(0.0, abs=1e-9)
    assert iso[1] == pytest.approx(1.0, abs=0.02)


def test_a_long_corridor_plan_is_less_isotropic_than_a_hall():
    hall = Plan(12.0, 12.0, 0.05).room("hall", (1.0, 1.0, 11.0, 11.0)).world()
    corridor = Plan(62.0, 4.0, 0.05).room("corridor", (1.0, 1.0, 61.0, 3.0)).world()
    config = SightlineConfig(spacing_m=1.0, beams=180, isotropy_range_m=10.0)
    hall_iso = sightline_features(hall, config)[ISOTROPY_COLUMN]
    corridor_iso = sightline_features(corridor, config)[ISOTROPY_COLUMN]
    assert hall_iso > 0.8
    assert corridor_iso < 0.2          # only points within 10 m of an end see the end wall
    assert corridor_iso == pytest.approx(mean_isotropy(sight_lines(corridor, config), 10.0))


def test_no_points_give_zero():
    assert mean_isotropy(np.zeros((0, 360)), 30.0) == 0.0
