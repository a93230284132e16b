"""Layout XML floor plans (spaces, WALL/PORTAL segments, scale) → World.

Format (``floorplans/layouts``): ``<scale>`` says N drawing units = M cm, so one unit is
M / (100·N) m; each ``<space>`` has a ``<bounding_polygon>``, ``<linesegment>`` elements of class
WALL or PORTAL, and ``<portal>`` entries naming a PORTAL segment and the two space ids. Drawing
coordinates have y down; the World has y up and its bitmap centred on the origin (0, 0), which is
the centre of the extent of every ``<point>`` in the file.

Rasterisation (pixel-centre rule; details in :mod:`slam_predict.world.layout_raster`):
1. free = union of the space polygons (everything else, including the outside, is obstacle);
2. every space outline edge and every WALL segment is drawn as a wall ``wall_thickness`` m
   thick, centred on the line, with square caps;
3. every portal is opened as a door (the rule of :mod:`slam_predict.world.layout_doors`):
   PORTAL segments are degenerate (zero length, often one point shared by both spaces), so a
   door ``door_width`` m wide is cut through the shared wall, centred on the portal point(s),
   as deep as needed to join the two spaces;
4. spaces still cut off (a few have no portal, or only portals to the outside) get an inferred
   door in the middle of their longest shared wall (``provenance['inferred_doors']``); free
   cells still unreachable are closed (``provenance['closed_islands_m2']``, ``rooms_closed``).

Resolution: the grid extent is a whole number of 0.1 m cells, centred on the origin, and the
plan is rasterised on samples ``sample_m`` (0.05 m) apart, a cell being an obstacle when any of
its samples is (:func:`slam_predict.world.layout_raster.rasterise_sampled`). At 0.05 m/px this
is the pixel-centre raster; at 0.10 m/px it is that raster's 2 x 2 "any" reduction, i.e. the
features' 0.1 m working grid of the 0.05 m/px world, so the features do not depend on which of
the two resolutions a plan is loaded at (issue #6). Finer resolutions use their own pixel
centres (the area checks at 0.02 m/px).

Ground truth kept on the World: one :class:`Room` per space (polygon in world metres, label) and
one :class:`Door` per opened portal (segment along the wall, the two space ids).
"""
from __future__ import annotations

import logging
import os
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from slam_predict.errors import InputError, require_file
from slam_predict.world.model import Door, Room, World

LOG = logging.getLogger(__name__)
UNIT_TO_M = {"cm": 0.01, "m": 1.0, "mm": 0.001}
DEFAULT_RESOLUTION = 0.05
DEFAULT_WALL = 0.15
DEFAULT_DOOR = 0.9
DEFAULT_SAMPLE = 0.05  # m: sample spacing of the conservative rasterisation


@dataclass
class Space:
    """One space in drawing units (y down): outline, WALL segments, portal points → other space."""

    id: str
    label: str
    kind: str
    polygon: np.ndarray
    walls: np.ndarray
    portals: list[tuple[np.ndarray, str]] = field(default_factory=list)


@dataclass
class Layout:
    """A parsed layout XML: metres per drawing unit, the spaces, the integer point extent."""

    path: str
    unit_m: float
    building_type: str
    spaces: list[Space]
    extent: tuple[float, float, float, float]  # min_x, min_y, max_x, max_y (units, truncated)


@dataclass(frozen=True)
class Frame:
    """Drawing units → world metres: x = (u − cx)·sx, y = −(v − cy)·sy (sy < 0 mirrors)."""

    sx: float
    sy: float
    cx: float
    cy: float

    def apply(self, pts) -> np.ndarray:
        """World (x, y) in m of drawing points (..., 2)."""
        pts = np.asarray(pts, dtype=float)
        return np.stack([(pts[..., 0] - self.cx) * self.sx, -(pts[..., 1] - self.cy) * self.sy],
                        axis=-1)


def _coord(point: ET.Element) -> tuple[float, float]:
    """(x, y) of a ``<point>``; ValueError when an attribute is missing or not a finite number."""
    x, y = float(point.get("x", "nan")), float(point.get("y", "nan"))
    if not (np.isfinite(x) and np.isfinite(y)):
        raise ValueError(f"<point x={point.get('x')!r} y={point.get('y')!r}>")
    return x, y


def _points(element: ET.Element | None) -> np.ndarray:
    if element is None:
        return np.zeros((0, 2))
    return np.array([_coord(p) for p in element.findall("point")], dtype=float).reshape(-1, 2)


def _text(element: ET.Element | None, default: str = "") -> str:
    if element is None or element.text is None:
        return default
    return element.text.strip()


def _scale(root: ET.Element, path: str) -> float:
    """Metres per drawing unit from ``<scale>``; InputError when missing or ≤ 0."""
    scale = root.find("scale")
    if scale is None:
        raise InputError("layout has no <scale> (N pixel = M cm)", path)
    try:
        units = float(_text(scale.find("represented_distance/value")))
        real = float(_text(scale.find("real_distance/value")))
    except ValueError:
        raise InputError("layout <scale> values are missing or not numbers", path) from None
    um = _text(scale.find("real_distance/um"), "cm").lower()
    if um not in UNIT_TO_M:
        raise InputError(f"layout <scale> real distance unit '{um}' is not one of "
                         f"{sorted(UNIT_TO_M)}", path)
    if not (units > 0 and real > 0):
        raise InputError(f"layout <scale> must be > 0 (got {units:g} units = {real:g} {um})",
                         path)
    return real * UNIT_TO_M[um] / units


def _space(element: ET.Element, path: str) -> Space | None:
    polygon = _points(element.find("bounding_polygon"))
    if len(polygon) >= 2 and np.array_equal(polygon[0], polygon[-1]):
        polygon = polygon[:-1]
    sid = element.get("id", "")
    if len(polygon) < 3:
        LOG.warning("%s: space %s has no usable bounding polygon; skipped", path, sid)
        return None
    segments = {}
    walls = []
    for seg in element.findall("space_representation/linesegment"):
        pts = _points(seg)
        if len(pts) != 2:
            continue
        segments[seg.get("id")] = pts
        if _text(seg.find("class")).upper() == "WALL":
            walls.append(pts)
    portals = []
    for portal in element.findall("portals/portal"):
        pts = segments.get(_text(portal.find("linesegment")))
        targets = [_text(t) for t in portal.findall("target/id")]
        others = [t for t in targets if t != sid]
        if pts is None or len(others) != 1:
            continue
        portals.append((pts.mean(axis=0), others[0]))
    return Space(id=sid, label=_text(element.find("labels/label")),
                 kind=_text(element.find("labels/type")), polygon=polygon,
                 walls=np.array(walls, dtype=float).reshape(-1, 2, 2), portals=portals)


def parse_layout(path: os.PathLike | str) -> Layout:
    """Read a layout XML file; InputError for a missing/malformed file, no scale or no spaces."""
    path = require_file(path, "layout XML")
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        raise InputError(f"malformed XML ({exc})", path) from None
    unit = _scale(root, path)
    try:
        spaces = [_space(e, path) for e in root.findall("floor/spaces/space")]
        all_pts = [_coord(p) for p in root.iter("point")]
    except ValueError as exc:
        raise InputError(f"bad point coordinate {exc}", path) from None
    spaces = [s for s in spaces if s is not None]
    if not spaces:
        raise InputError("layout has no spaces (floor/spaces/space with a bounding polygon)",
                         path)
    xs = [int(x) for x, _ in all_pts]  # truncated to int, as the thesis' xmlToWorld.py
    ys = [int(y) for _, y in all_pts]
    return Layout(path=path, unit_m=unit, spaces=spaces,
                  building_type=_text(root.find("building_type/main_type")),
                  extent=(min(xs), min(ys), max(xs), max(ys)))


def centred_frame(layout: Layout) -> Frame:
    """The isotropic frame at the layout's own scale, centred on its point extent."""
    x0, y0, x1, y1 = layout.extent
    return Frame(layout.unit_m, layout.unit_m, (x0 + x1) / 2.0, (y0 + y1) / 2.0)


def stretched_frame(layout: Layout, size_m: tuple[float, float], mirror: bool = False) -> Frame:
    """The frame that maps the layout's point extent exactly onto ``size_m`` (W, H m), as the
    thesis' Stage worlds did (``floorplan size [W H]`` stretches the bitmap). ``mirror`` keeps
    the drawing's y axis as world y (a vertical mirror image of the drawing)."""
    x0, y0, x1, y1 = layout.extent
    sy = size_m[1] / max(y1 - y0, 1)
    return Frame(size_m[0] / max(x1 - x0, 1), -sy if mirror else sy,
                 (x0 + x1) / 2.0, (y0 + y1) / 2.0)


def layout_world(layout: Layout, frame: Frame, grid, wall_thickness: float,
                 door_width: float, name: str, sample_m: float | None = None) -> World:
    """Rasterise ``layout`` onto ``grid`` (a :class:`raster.Grid`) through ``frame``; with
    ``sample_m`` (m) conservatively: a cell is an obstacle when any of its samples ``sample_m``
    apart is (:func:`layout_raster.rasterise_sampled`)."""
    from slam_predict.world.layout_doors import find_doors
    from slam_predict.world.layout_raster import rasterise, rasterise_sampled

    rooms = [Room(id=s.id, polygon=frame.apply(s.polygon), label=s.label) for s in layout.spaces]
    doors = find_doors(layout, frame, rooms, door_width)
    walls = [frame.apply(s.walls) for s in layout.spaces]
    if sample_m is None:
        free, inferred, report = rasterise(rooms, walls, doors, grid, wall_thickness, door_width)
    else:
        free, inferred, report = rasterise_sampled(rooms, walls, doors, grid, wall_thickness,
                                                   door_width, sample_m)
    if not free.any():
        raise InputError("layout rasterises to no free space", layout.path)
    provenance = {"source": layout.path, "format": "layout-xml", "unit_m": layout.unit_m,
                  "building_type": layout.building_type, "wall_thickness": wall_thickness,
                  "door_width": door_width, "sample_m": sample_m, **report}
    world_doors = [Door(segment=d.segment, rooms=d.rooms) for d in list(doors) + inferred]
    return World(name=name, occupied=~free, resolution=grid.resolution, origin=grid.origin,
                 rooms=rooms, doors=world_doors, provenance=provenance)


def _check_positive(value: float, what: str, path: str) -> None:
    if not value > 0:
        raise InputError(f"{what} must be > 0 (got {value:g})", path)


def rasterise_layout(path: os.PathLike | str, resolution: float | None = None,
                     wall_thickness: float = DEFAULT_WALL, door_width: float = DEFAULT_DOOR,
                     sample_m: float | None = DEFAULT_SAMPLE) -> World:
    """A layout XML as a World at its own scale, centred on the origin, without a start pose
    (``provenance['start_given']`` is False). The grid extent is whole 0.1 m cells and the
    plan is sampled every ``sample_m`` m (module docstring, "Resolution")."""
    from slam_predict.world.layout_raster import LATTICE_M, nested_cells
    from slam_predict.world.raster import Grid

    resolution = DEFAULT_RESOLUTION if resolution is None else resolution
    layout = parse_layout(path)
    for value, what in ((resolution, "resolution"), (wall_thickness, "wall thickness"),
                        (door_width, "door width")):
        _check_positive(value, what, layout.path)
    frame = centred_frame(layout)
    x0, y0, x1, y1 = layout.extent
    half_w, half_h = (x1 - x0) * frame.sx / 2.0, (y1 - y0) * frame.sy / 2.0
    margin = wall_thickness + 2 * max(resolution, LATTICE_M)
    grid = Grid(nested_cells(2 * (half_h + margin), resolution, ceil=True),
                nested_cells(2 * (half_w + margin), resolution, ceil=True), resolution)
    name = os.path.splitext(os.path.basename(layout.path))[0]
    world = layout_world(layout, frame, grid, wall_thickness, door_width, name, sample_m)
    world.provenance["start_given"] = False
    return world


def load_layout(path: os.PathLike | str, resolution: float | None = None,
                wall_thickness: float = DEFAULT_WALL, door_width: float = DEFAULT_DOOR,
                start: Sequence[float] | None = None, snap_start: bool = False,
                sample_m: float | None = DEFAULT_SAMPLE) -> World:
    """Load a layout XML as a World at ``resolution`` m/px (default 0.05).

    Walls are ``wall_thickness`` m thick, doors ``door_width`` m wide; ``start`` is
    (x, y[, yaw]) in m, m, deg (default: the start-pose rule of :mod:`slam_predict.world.start`);
    ``snap_start`` moves a start pose in a wall to the nearest free cell; ``sample_m`` (m) is
    the sample spacing of the conservative rasterisation (None: pixel centres at
    ``resolution``).
    """
    from slam_predict.world.start import resolve_start

    world = rasterise_layout(path, resolution, wall_thickness, door_width, sample_m)
    return resolve_start(world, start, snap_start)
