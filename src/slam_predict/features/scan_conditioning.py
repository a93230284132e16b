"""How well a laser's view of the walls pins down the robot's position (issue #18).

A scan matcher fixes the robot's translation along the normals of the walls it sees: a wall
seen head-on constrains motion across it and leaves motion along it free. For one scan, with
unit wall normals n_k at its hit points, the translational information is the 2 × 2 matrix
Σ n_k n_kᵀ (a point-to-line matcher's Hessian, up to the noise scale). Its *isotropy*, the
smaller eigenvalue over the larger, is 1 when walls face every way (a room's centre) and 0 when
they all face one way (a corridor whose ends lie beyond the range, where the matcher slides
along the corridor).

The wall normals come from the sight lines of :mod:`slam_predict.features.sightline`: two
neighbouring beams that both hit within the range, at hit points less than ``max_gap_m``
apart, see one wall segment, whose normal is perpendicular to the segment between the two
points. Farther apart, the beams are taken to straddle a corner or a doorway, and the pair
gives no normal. A scan without any normal has isotropy 0.

The plan feature ``sightline_isotropy`` is the isotropy averaged over the sight lines' floor
points, at GMapping's maxUrange of the campaigns (30 m).
"""
from __future__ import annotations

import numpy as np

ISOTROPY_COLUMN = "sightline_isotropy"
MAX_GAP_M = 0.75           # m: farther-apart neighbouring hits are not one wall


def wall_normals(distances: np.ndarray, range_m: float,
                 max_gap_m: float = MAX_GAP_M) -> tuple[np.ndarray, np.ndarray]:
    """Unit normals (nx, ny), shape (points, beams), of the wall segment between beam k and
    beam k + 1 (cyclic over 360°) of each row of ``distances`` (m, beams evenly spread over
    360° from angle 0); both 0 where the pair does not see one wall within ``range_m`` (m)."""
    d = np.asarray(distances, dtype=float)
    beams = d.shape[1]
    angles = np.arange(beams) * (2.0 * np.pi / beams)
    seen = np.where(d <= range_m, d, np.nan)
    x, y = seen * np.cos(angles), seen * np.sin(angles)
    dx, dy = np.roll(x, -1, axis=1) - x, np.roll(y, -1, axis=1) - y
    gap = np.hypot(dx, dy)
    one_wall = np.isfinite(gap) & (gap < max_gap_m) & (gap > 1e-9)
    safe = np.where(one_wall, gap, 1.0)
    return np.where(one_wall, -dy / safe, 0.0), np.where(one_wall, dx / safe, 0.0)


def scan_isotropy(distances: np.ndarray, range_m: float,
                  max_gap_m: float = MAX_GAP_M) -> np.ndarray:
    """Per row of ``distances`` (see :func:`wall_normals`): smaller over larger eigenvalue of
    Σ n nᵀ over the row's wall normals, in [0, 1]; 0 for a row without normals."""
    nx, ny = wall_normals(distances, range_m, max_gap_m)
    a, b, c = (nx * nx).sum(axis=1), (nx * ny).sum(axis=1), (ny * ny).sum(axis=1)
    half_trace = (a + c) / 2.0
    spread = np.sqrt(np.maximum(half_trace ** 2 - (a * c - b * b), 0.0))
    largest = half_trace + spread
    return np.where(largest > 0.0, (half_trace - spread) / np.where(largest > 0, largest, 1.0),
                    0.0)


def mean_isotropy(distances: np.ndarray, range_m: float,
                  max_gap_m: float = MAX_GAP_M) -> float:
    """The plan feature: :func:`scan_isotropy` averaged over the rows (0 for no rows)."""
    if np.asarray(distances).shape[0] == 0:
        return 0.0
    return float(scan_isotropy(distances, range_m, max_gap_m).mean())
