"""Building styles (office, school) and the per-building parameters drawn from them.

All lengths in metres. A style gives ranges; :func:`sample_params` draws one building's values
with the seeded generator it is given, so a seed fixes the whole building.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

Range = tuple[float, float]


@dataclass(frozen=True)
class Style:
    """Ranges for one kind of building (m, or probabilities)."""

    corridor_width: Range
    room_depth: Range
    room_width: Range
    small_room_width: Range
    small_room_prob: float
    hall_width: Range
    hall_prob: float
    door_width: Range
    hall_door_width: Range
    suite_door_prob: float
    max_wing: float
    room_labels: tuple[str, ...]
    small_labels: tuple[str, ...]
    hall_labels: tuple[str, ...]


STYLES: dict[str, Style] = {
    "office": Style(corridor_width=(1.6, 2.4), room_depth=(4.0, 6.5), room_width=(2.6, 6.0),
                    small_room_width=(1.8, 2.6), small_room_prob=0.15, hall_width=(8.0, 16.0),
                    hall_prob=0.08, door_width=(0.8, 1.0), hall_door_width=(1.2, 1.5),
                    suite_door_prob=0.1, max_wing=60.0,
                    room_labels=("OFFICE", "OFFICE", "SHARED OFFICE", "MEETING ROOM"),
                    small_labels=("WASHROOM", "STORAGE", "COPY ROOM"),
                    hall_labels=("OPENSPACE", "CONFERENCE HALL", "CANTEEN")),
    "school": Style(corridor_width=(2.4, 3.6), room_depth=(6.0, 8.5), room_width=(6.0, 9.0),
                    small_room_width=(2.5, 4.0), small_room_prob=0.25, hall_width=(12.0, 22.0),
                    hall_prob=0.1, door_width=(0.9, 1.2), hall_door_width=(1.2, 1.5),
                    suite_door_prob=0.05, max_wing=80.0,
                    room_labels=("CLASSROOM", "CLASSROOM", "CLASSROOM", "LAB", "OFFICE"),
                    small_labels=("WASHROOM", "STORAGE", "STAIRS"),
                    hall_labels=("GYM", "CANTEEN", "LIBRARY", "HALL")),
}
KINDS = tuple(STYLES)

# Spine shapes allowed per requested free area (m²): (upper bound, shapes).
SHAPES_BY_AREA = ((300.0, ("straight",)), (1200.0, ("straight", "L")),
                  (4000.0, ("L", "T", "U", "comb")),
                  (float("inf"), ("U", "ring", "comb", "ring")))


@dataclass(frozen=True)
class BuildingParams:
    """One building's drawn parameters (m)."""

    kind: str
    shape: str
    corridor_width: float
    depth_left: float
    depth_right: float
    wall_inner: float
    wall_outer: float
    split: float  # how the corridor length is shared between wings, in [0.3, 0.7]
    courtyard: bool
    court: float  # width of open courts between facing room bands (m)

    def to_dict(self) -> dict:
        """Plain dict (for metadata)."""
        return asdict(self)


def _uniform(rng: np.random.Generator, bounds: Range) -> float:
    return float(rng.uniform(bounds[0], bounds[1]))


def sample_params(kind: str, area_m2: float, rng: np.random.Generator) -> BuildingParams:
    """Draw a building's parameters for a requested free area (m²)."""
    style = STYLES[kind]
    shapes = next(s for bound, s in SHAPES_BY_AREA if area_m2 < bound)
    shape = str(shapes[int(rng.integers(len(shapes)))])
    depth_left = _uniform(rng, style.room_depth)
    depth_right = _uniform(rng, style.room_depth)
    if area_m2 < 200.0 and rng.random() < 0.5:
        depth_right = 0.0  # single-loaded corridor for very small buildings
    wall_inner = round(_uniform(rng, (0.1, 0.2)), 3)
    wall_outer = round(_uniform(rng, (max(0.2, wall_inner), 0.3)), 3)
    return BuildingParams(kind=kind, shape=shape,
                          corridor_width=_uniform(rng, style.corridor_width),
                          depth_left=depth_left, depth_right=depth_right,
                          wall_inner=wall_inner, wall_outer=wall_outer,
                          split=_uniform(rng, (0.35, 0.65)),
                          courtyard=bool(rng.random() < 0.7), court=_uniform(rng, (8.0, 16.0)))
