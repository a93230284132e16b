"""Exact rasterisation of polygons and thick segments onto a World-style grid.

The sampling rule is the pixel-centre rule: a cell belongs to a shape iff its centre lies inside
the shape (even-odd rule). This makes areas unbiased (no half-pixel growth as with anti-aliased
or "conservative" drawing), which the layout area checks rely on.

Coordinates: shapes are given in world metres (x right, y up); a :class:`Grid` maps them onto a
bitmap of ``rows`` x ``cols`` cells of ``resolution`` m whose centre is the world point
``origin`` — the same convention as :class:`slam_predict.world.model.World`.
"""
from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numba
import numpy as np
from scipy import ndimage

FOUR_CONNECTED = ndimage.generate_binary_structure(2, 1)


@dataclass(frozen=True)
class Grid:
    """A bitmap frame: ``rows`` x ``cols`` cells of ``resolution`` m centred on ``origin`` (m)."""

    rows: int
    cols: int
    resolution: float
    origin: tuple[float, float] = (0.0, 0.0)

    @classmethod
    def covering(cls, xmin: float, ymin: float, xmax: float, ymax: float, resolution: float,
                 margin: float = 0.0) -> Grid:
        """The smallest grid centred on the box centre that holds the box plus ``margin`` m."""
        cols = int(math.ceil((xmax - xmin + 2 * margin) / resolution - 1e-9))
        rows = int(math.ceil((ymax - ymin + 2 * margin) / resolution - 1e-9))
        return cls(max(rows, 1), max(cols, 1), resolution, ((xmin + xmax) / 2, (ymin + ymax) / 2))

    @property
    def shape(self) -> tuple[int, int]:
        """(rows, cols)."""
        return self.rows, self.cols

    def to_px(self, xy) -> np.ndarray:
        """Continuous pixel coordinates (u right, v down; cell (r, c) spans [c, c+1) x [r, r+1))."""
        xy = np.asarray(xy, dtype=float)
        u = (xy[..., 0] - self.origin[0]) / self.resolution + self.cols / 2.0
        v = self.rows / 2.0 - (xy[..., 1] - self.origin[1]) / self.resolution
        return np.stack([u, v], axis=-1)

    def window(self, r0: int, r1: int, c0: int, c1: int) -> Grid:
        """The grid of the sub-bitmap ``[r0:r1, c0:c1]`` (same world coordinates)."""
        x = self.origin[0] + ((c0 + c1) / 2.0 - self.cols / 2.0) * self.resolution
        y = self.origin[1] + (self.rows / 2.0 - (r0 + r1) / 2.0) * self.resolution
        return Grid(r1 - r0, c1 - c0, self.resolution, (x, y))

    def empty(self, value: bool = False) -> np.ndarray:
        """A bool bitmap of this grid filled with ``value``."""
        return np.full(self.shape, value, dtype=bool)


@numba.njit(cache=True)
def _fill_polygons(mask, u, v, starts, value):
    """Scanline fill (pixel-centre, even-odd) of polygons packed in u, v.

    ``starts`` has n+1 offsets.
    """
    rows, cols = mask.shape
    crossings = np.empty(u.shape[0], dtype=np.float64)
    for p in range(starts.shape[0] - 1):
        a, b = starts[p], starts[p + 1]
        n = b - a
        if n < 3:
            continue
        vmin, vmax = v[a:b].min(), v[a:b].max()
        r0 = max(0, int(math.ceil(vmin - 0.5)))
        r1 = min(rows - 1, int(math.floor(vmax - 0.5)))
        for r in range(r0, r1 + 1):
            y = r + 0.5
            k = 0
            for i in range(n):
                j = i + 1 if i + 1 < n else 0
                y0, y1 = v[a + i], v[a + j]
                if (y0 <= y < y1) or (y1 <= y < y0):
                    x0, x1 = u[a + i], u[a + j]
                    crossings[k] = x0 + (y - y0) * (x1 - x0) / (y1 - y0)
                    k += 1
            xs = np.sort(crossings[:k])
            for q in range(0, k - 1, 2):
                c0 = max(0, int(math.ceil(xs[q] - 0.5)))
                c1 = min(cols, int(math.ceil(xs[q + 1] - 0.5)))
                for c in range(c0, c1):
                    mask[r, c] = value


def fill_polygons(mask: np.ndarray, grid: Grid, polygons: Iterable[np.ndarray],
                  value=True) -> None:
    """Set to ``value`` every cell of ``mask`` whose centre is inside one of ``polygons`` (m).

    ``mask`` may be bool or integer (e.g. a label image); ``value`` is cast to its dtype."""
    polygons = [np.asarray(p, dtype=float).reshape(-1, 2) for p in polygons]
    polygons = [p for p in polygons if len(p) >= 3]
    if not polygons:
        return
    packed = grid.to_px(np.concatenate(polygons))
    starts = np.cumsum([0] + [len(p) for p in polygons]).astype(np.int64)
    _fill_polygons(mask, np.ascontiguousarray(packed[:, 0]), np.ascontiguousarray(packed[:, 1]),
                   starts, mask.dtype.type(value))


def segment_rectangle(p0, p1, half_width: float, half_length_extra: float) -> np.ndarray:
    """Corners (4, 2) of the rectangle around segment p0-p1 (m): ``half_width`` m to each side,
    extended by ``half_length_extra`` m beyond both ends. Zero-length segments give a square."""
    p0, p1 = np.asarray(p0, dtype=float), np.asarray(p1, dtype=float)
    delta = p1 - p0
    length = float(np.hypot(*delta))
    d = delta / length if length > 0 else np.array([1.0, 0.0])
    n = np.array([-d[1], d[0]])
    a, b = p0 - d * half_length_extra, p1 + d * half_length_extra
    return np.array([a + n * half_width, b + n * half_width, b - n * half_width,
                     a - n * half_width])


def draw_segments(mask: np.ndarray, grid: Grid, segments: Sequence, thickness: float,
                  value: bool = True) -> None:
    """Draw segments ((N, 2, 2), m) ``thickness`` m wide with square caps (extended by half the
    thickness, so walls meeting at a corner close it). Zero-length segments are skipped."""
    segments = np.asarray(segments, dtype=float).reshape(-1, 2, 2)
    lengths = np.hypot(*(segments[:, 1] - segments[:, 0]).T)
    half = thickness / 2.0
    rects = [segment_rectangle(s[0], s[1], half, half) for s in segments[lengths > 0]]
    fill_polygons(mask, grid, rects, value)


def fill_box(mask: np.ndarray, grid: Grid, xmin: float, ymin: float, xmax: float, ymax: float,
             value: bool = True) -> None:
    """Axis-aligned box (m) by the pixel-centre rule, with array slicing (fast path)."""
    u0, v1 = grid.to_px((xmin, ymin))
    u1, v0 = grid.to_px((xmax, ymax))
    c0 = max(0, int(math.ceil(u0 - 0.5)))
    c1 = min(grid.cols, int(math.ceil(u1 - 0.5)))
    r0 = max(0, int(math.ceil(v0 - 0.5)))
    r1 = min(grid.rows, int(math.ceil(v1 - 0.5)))
    if c1 > c0 and r1 > r0:
        mask[r0:r1, c0:c1] = value


def label_free(free: np.ndarray) -> tuple[np.ndarray, int]:
    """4-connected components of free cells: (labels, count). 4-connectivity because a robot
    cannot squeeze through a diagonal pixel contact."""
    labels, count = ndimage.label(free, structure=FOUR_CONNECTED)
    return labels, int(count)


def polygon_area(polygon: np.ndarray) -> float:
    """Shoelace area (absolute) of a polygon (N, 2)."""
    p = np.asarray(polygon, dtype=float)
    x, y = p[:, 0], p[:, 1]
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def polygon_perimeter(polygon: np.ndarray) -> float:
    """Perimeter of a closed polygon (N, 2)."""
    p = np.asarray(polygon, dtype=float)
    return float(np.hypot(*(np.roll(p, -1, axis=0) - p).T).sum())


def warmup() -> None:
    """Compile the kernels on a tiny input."""
    grid = Grid(4, 4, 1.0)
    mask = grid.empty()
    triangle = np.array([[-1.0, -1.0], [1.0, -1.0], [0.0, 1.0]])
    fill_polygons(mask, grid, [triangle])
    fill_polygons(np.zeros(grid.shape, dtype=np.int32), grid, [triangle], 1)
