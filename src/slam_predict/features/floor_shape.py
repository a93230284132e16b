"""How elongated a plan's floor is (issue #18).

Kümmerle's error, as the project measures it, averages the relative-pose error over pairs of
poses drawn at random along the whole exploration. An error in the map's heading makes the
relative translation between two poses wrong in proportion to how far apart they are, so the
same drift costs more in a long, thin building than in a compact one of the same area: its
poses are farther apart on average.

The floor is the sight lines' grid of points where a robot can stand
(:func:`slam_predict.features.sightline.sample_points`, one per ``spacing_m`` square). Each
point stands for its square, so the floor's 2 × 2 covariance is that of the points plus the
square's own, spacing² / 12 on the diagonal. Its *elongation* is √(λmax / λmin): 1 for a square
or a disc, a / b for an a × b rectangle, whatever its orientation.
"""
from __future__ import annotations

import math

import numpy as np

ELONGATION_COLUMN = "floor_elongation"


def floor_covariance(x_m: np.ndarray, y_m: np.ndarray, spacing_m: float) -> np.ndarray:
    """2 × 2 covariance (m²) of the union of ``spacing_m`` squares centred on the points (m)."""
    points = np.column_stack([np.asarray(x_m, dtype=float), np.asarray(y_m, dtype=float)])
    if points.shape[0] == 0:
        raise ValueError("no floor points")
    centred = points - points.mean(axis=0)
    return centred.T @ centred / points.shape[0] + np.eye(2) * (spacing_m ** 2 / 12.0)


def elongation(x_m: np.ndarray, y_m: np.ndarray, spacing_m: float) -> float:
    """√(λmax / λmin) of :func:`floor_covariance`: ≥ 1, a / b for an a × b rectangle."""
    smaller, larger = np.linalg.eigvalsh(floor_covariance(x_m, y_m, spacing_m))
    return math.sqrt(larger / smaller)
