"""Predictions for a laser between the trained angular resolutions.

The robot campaigns collect a few resolutions (0.25°, 0.5° and 1° between beams). Trees split
between two of them at one value, so a laser at 0.35° would read the 0.25° prediction in full
and one at 0.4° the 0.5° one. A robot-aware model that learns the resolution therefore
predicts a laser between two trained resolutions by interpolating, on log scales (the
resolution's and the prediction's), between its predictions at those two
(:func:`brackets`, :func:`blend`); at a trained resolution, or beyond the trained ones, the
prediction is the model's own. The interpolation keeps every component monotone in the other
robot inputs (both ends are, and the weights depend on the resolution alone).
"""
from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

from slam_predict.learn.robot.inputs import DESIGN_RESOLUTION_DEG, RESOLUTION_INPUT

BOUNDS = ("value", "low", "high")


def trained_levels(card: Mapping) -> list[float]:
    """The laser angular resolutions of a card's training runs, deg (``design.
    angular_resolution_deg``; the design's 0.5° for cards without the field)."""
    return [float(v) for v in card["design"].get("angular_resolution_deg")
            or [DESIGN_RESOLUTION_DEG]]


def trained_range(card: Mapping) -> tuple[float, float]:
    """(finest, coarsest) laser angular resolution of a card's training runs, deg."""
    trained = trained_levels(card)
    return min(trained), max(trained)


def resolution_warning(card: Mapping, names: Sequence[str], value: float) -> str | None:
    """A line, with what to do, when the laser's angular resolution ``value`` (deg) lies
    outside the card's training runs' range (1 % tolerance); None inside it, or when the
    model learns it (``names``: its inputs; then its input-range check covers it)."""
    low, high = trained_range(card)
    if low / 1.01 <= value <= high * 1.01 or RESOLUTION_INPUT in names:
        return None
    trained = f"{low:g} deg" if low == high else f"{low:g}-{high:g} deg"
    side = "finer" if value < low else "coarser"
    return (f"laser angular resolution {value:.4g} deg is {side} than every training run's "
            f"({trained}; not a model input): measure this robot on the plan with "
            "--simulate 3 to check the prediction")


def brackets(levels: Sequence[float], value: float) -> list[tuple[float, float]]:
    """[(resolution deg, weight)]: the two trained ``levels`` around ``value`` (deg) with
    weights linear in log(resolution) and summing to 1; [(value, 1.0)] at a level, outside
    the levels' span or with fewer than two."""
    levels = sorted({float(v) for v in levels})
    if len(levels) < 2 or not levels[0] < value < levels[-1] or value in levels:
        return [(float(value), 1.0)]
    high = min(v for v in levels if v > value)
    low = max(v for v in levels if v < value)
    t = (math.log(value) - math.log(low)) / (math.log(high) - math.log(low))
    return [(low, 1.0 - t), (high, t)]


def blend(parts: Sequence[tuple[float, Mapping[str, dict]]]) -> dict[str, dict]:
    """The weighted geometric mean (arithmetic where a number is ≤ 0) of the ``value``,
    ``low`` and ``high`` of each component of the weighted predictions ``parts``; None stays
    None. Other keys are the first part's."""
    first = parts[0][1]
    out = {}
    for component, entry in first.items():
        merged = dict(entry)
        for key in BOUNDS:
            numbers = [(w, p[component][key]) for w, p in parts]
            if any(v is None for _, v in numbers):
                continue
            if all(v > 0 for _, v in numbers):
                merged[key] = math.exp(sum(w * math.log(v) for w, v in numbers))
            else:
                merged[key] = sum(w * v for w, v in numbers)
        out[component] = merged
    return out


def between_resolutions(model, plan_features: Mapping[str, float],
                        robot: Mapping[str, float], confidence: float) -> dict[str, dict]:
    """``model.predict_at`` (a :class:`~slam_predict.learn.robot.predict.RobotModel`) for the
    robot, interpolated between the trained resolutions (the card's
    ``design.angular_resolution_deg``) when the model learns the resolution and the robot's
    lies between two of them."""
    if RESOLUTION_INPUT not in model.names or RESOLUTION_INPUT not in robot:
        return model.predict_at(plan_features, robot, confidence)
    parts = brackets(trained_levels(model.card), float(robot[RESOLUTION_INPUT]))
    if len(parts) == 1:
        return model.predict_at(plan_features, robot, confidence)
    return blend([(weight, model.predict_at(plan_features,
                                            {**robot, RESOLUTION_INPUT: level}, confidence))
                  for level, weight in parts])
