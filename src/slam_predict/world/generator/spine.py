"""Corridor spines: the centre lines of a building's corridors (its *wings*).

A wing is an axis-aligned corridor centre line p → q with a band of rooms on each side
(``depth_left``/``depth_right`` m; left = the side 90° counter-clockwise from p → q). The
total centre-line length (m) is given; the shapes spend it as follows:

- ``straight``: one wing;
- ``L``: two wings meeting at a corner;
- ``T``: a bar and a stem leaving its middle;
- ``U``: a base and two arms (the court between the arms is open to the outside);
- ``comb``: a spine with as many perpendicular teeth as the length needs (an E for three; a
  fishbone with teeth on both sides from four on);
- ``ring``: corridors around inner courtyards — one ring, or for long lengths a grid of
  nx × ny courtyards (corridors along every grid line, crossing every ``pitch`` m). Without
  courtyard, back-to-back rooms fill the centres instead.

No wing (no grid pitch) is longer than the style's ``max_wing`` (1.5× for a bar or a spine). A
shape that the length cannot fill falls back to a simpler one (ring → U → L → straight,
comb → T → L); a shape that would need longer wings grows into a bigger one
(straight → L → T → comb → ring, U → comb).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from slam_predict.world.generator.params import STYLES, BuildingParams

ARM_MIN = 3.0  # m: an arm must stick out at least this far beyond the band it leaves
SHORT, LONG = "short", "long"


@dataclass(frozen=True)
class Wing:
    """A corridor centre line (m) with the room band depths on its left and right (m)."""

    p: tuple
    q: tuple
    depth_left: float
    depth_right: float

    @property
    def length(self) -> float:
        """Centre-line length, m."""
        return float(np.hypot(self.q[0] - self.p[0], self.q[1] - self.p[1]))


Result = tuple[str | None, list[Wing]]  # (None | SHORT | LONG, wings)


def _band(params: BuildingParams) -> float:
    """Half the building depth of a wing: corridor half-width + deepest band (m)."""
    return params.corridor_width / 2.0 + max(params.depth_left, params.depth_right)


def _max_wing(params: BuildingParams) -> float:
    return STYLES[params.kind].max_wing


def _wing(p, q, params: BuildingParams) -> Wing:
    return Wing(tuple(map(float, p)), tuple(map(float, q)), params.depth_left,
                params.depth_right)


def _straight(params: BuildingParams, length: float) -> Result:
    if length > 1.5 * _max_wing(params):
        return LONG, []
    return None, [_wing((0, 0), (length, 0), params)]


def _l_shape(params: BuildingParams, length: float) -> Result:
    a = params.split * length
    b = length - a
    if b < _band(params) + ARM_MIN or a < 2 * _band(params):
        return SHORT, []
    if max(a, b) > 1.2 * _max_wing(params):
        return LONG, []
    return None, [_wing((0, 0), (a, 0), params), _wing((a, 0), (a, b), params)]


def _t_shape(params: BuildingParams, length: float) -> Result:
    a = params.split * length
    b = length - a
    if b < _band(params) + ARM_MIN or a < 4 * _band(params):
        return SHORT, []
    if a > 1.5 * _max_wing(params) or b > _max_wing(params):
        return LONG, []
    return None, [_wing((-a / 2, 0), (a / 2, 0), params), _wing((0, 0), (0, -b), params)]


def _u_shape(params: BuildingParams, length: float) -> Result:
    a = max(params.split * length, 2 * _band(params) + params.court)
    b = (length - a) / 2.0
    if b < _band(params) + ARM_MIN:
        return SHORT, []
    if a > 1.5 * _max_wing(params) or b > _max_wing(params):
        return LONG, []
    return None, [_wing((0, 0), (a, 0), params), _wing((0, 0), (0, b), params),
                  _wing((a, 0), (a, b), params)]


def _comb(params: BuildingParams, length: float) -> Result:
    spacing = 2 * _band(params) + params.court
    tooth = min(_max_wing(params), max(_band(params) + ARM_MIN, 0.3 * length))
    teeth = max(2, int(math.ceil((length + spacing) / (spacing + tooth))))
    # teeth leave the spine upwards; from four teeth on, also downwards (a fishbone)
    positions = teeth if teeth < 4 else int(math.ceil(teeth / 2))
    spine = (positions - 1) * spacing
    tooth = (length - spine) / teeth
    if tooth < _band(params) + ARM_MIN:
        return SHORT, []
    if spine > 1.5 * _max_wing(params):
        return LONG, []
    wings = [_wing((0, 0), (spine, 0), params)]
    wings += [_wing((i * spacing, 0), (i * spacing, tooth), params) for i in range(positions)]
    wings += [_wing((i * spacing, 0), (i * spacing, -tooth), params)
              for i in range(teeth - positions)]
    return None, wings


def _grid_size(length: float, pitch: float, min_pitch: float) -> tuple[int, int, float]:
    """(nx, ny, fitted pitch m) of the courtyard grid whose corridor length is ``length``: the
    grid (nx = ny or ny + 1) whose fitted pitch is closest to the nominal ``pitch`` and at
    least ``min_pitch`` (one ring when even that is too small)."""
    best = None
    for ny in range(1, 16):
        for nx in (ny, ny + 1):
            fitted = length / ((ny + 1) * nx + (nx + 1) * ny)  # corridor length in pitches
            if fitted >= min_pitch and (best is None or abs(fitted - pitch) < abs(best[2]
                                                                                  - pitch)):
                best = (nx, ny, fitted)
    return best or (1, 1, length / 4.0)


def _ring(params: BuildingParams, length: float) -> Result:
    cw = params.corridor_width
    if params.courtyard:
        min_pitch = cw + 2 * params.depth_left + 6.0
    else:
        min_pitch = cw + 6.0  # back-to-back bands at least 3 m deep
    nominal = cw + 2 * params.depth_left + params.court
    nx, ny, pitch = _grid_size(length, nominal, min_pitch)
    if pitch < min_pitch:
        return SHORT, []
    # without courtyard the bands meet back to back (clipped where they overlap)
    d_in = params.depth_left if params.courtyard else (pitch - cw) / 2.0 + 0.5
    d_out = params.depth_right
    wings = []
    for j in range(ny + 1):  # horizontal lines, left = up
        wings.append(Wing((0.0, j * pitch), (nx * pitch, j * pitch),
                          d_in if j < ny else d_out, d_in if j > 0 else d_out))
    for i in range(nx + 1):  # vertical lines, left = -x
        wings.append(Wing((i * pitch, 0.0), (i * pitch, ny * pitch),
                          d_in if i > 0 else d_out, d_in if i < nx else d_out))
    return None, wings


BUILDERS = {"straight": _straight, "L": _l_shape, "T": _t_shape, "U": _u_shape,
            "ring": _ring, "comb": _comb}
SIMPLER = {"ring": "U", "U": "L", "L": "straight", "comb": "T", "T": "L"}
BIGGER = {"straight": "L", "L": "T", "T": "comb", "U": "comb", "comb": "ring"}


def make_spine(params: BuildingParams, length: float) -> tuple[str, list[Wing]]:
    """(shape actually used, wings) for a total corridor centre-line length (m)."""
    shape, seen = params.shape, set()
    while True:
        seen.add(shape)
        status, wings = BUILDERS[shape](params, length)
        if status is None:
            return shape, wings
        following = (SIMPLER if status == SHORT else BIGGER).get(shape)
        if following is None or following in seen:  # cannot do better: the plainest layout
            return "straight", [_wing((0, 0), (length, 0), params)]
        shape = following
