"""Grid geometry and per-particle maps stored like openslam_gmapping's HierarchicalArray2D.

A particle map is a small int32 table of patch ids (one entry per 32 x 32-cell patch, -1 = not
allocated yet) into a :class:`PatchPool` shared by all particles. Copying a particle copies only
its table (the patches gain a reference); a patch is copied before it is written while another
map still refers to it (copy-on-write). Patches are allocated lazily where hits land, so memory
follows the mapped walls, never the 200 m x 200 m nominal area. Maps grow by ``ENLARGE_STEP``
beyond a scan that leaves them (computeActiveArea's rule). Units: m.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from slam_predict.slam.gmapping import kernels
from slam_predict.slam.gmapping.params import ENLARGE_STEP, PATCH_MAGNITUDE

PATCH = 1 << PATCH_MAGNITUDE
Window = tuple[int, int, int, int]  # patch index range (pxmin, pymin, pxmax, pymax), max excluded


@dataclass
class Geometry:
    """openslam_gmapping Map geometry: centre (m), cell size (m), centre cell, size in patches."""

    cx: float
    cy: float
    delta: float
    sx2: int
    sy2: int
    nx: int
    ny: int

    @classmethod
    def particle_map(cls, xmin: float, ymin: float, xmax: float, ymax: float,
                     delta: float) -> Geometry:
        """Map(center, worldSizeX, worldSizeY, delta): the particle maps' initial geometry."""
        nx = int(math.ceil((xmax - xmin) / delta)) >> PATCH_MAGNITUDE
        ny = int(math.ceil((ymax - ymin) / delta)) >> PATCH_MAGNITUDE
        return cls((xmin + xmax) * 0.5, (ymin + ymax) * 0.5, delta,
                   (nx * PATCH) >> 1, (ny * PATCH) >> 1, nx, ny)

    @classmethod
    def bounded(cls, xmin: float, ymin: float, xmax: float, ymax: float,
                delta: float) -> Geometry:
        """Map(center, xmin, ymin, xmax, ymax, delta): the published map's geometry."""
        cx, cy = (xmin + xmax) / 2.0, (ymin + ymax) / 2.0
        nx = int(math.ceil((xmax - xmin) / delta)) >> PATCH_MAGNITUDE
        ny = int(math.ceil((ymax - ymin) / delta)) >> PATCH_MAGNITUDE
        return cls(cx, cy, delta, kernels.c_round((cx - xmin) / delta),
                   kernels.c_round((cy - ymin) / delta),
                   nx, ny)

    @property
    def size(self) -> tuple[int, int]:
        """Map size in cells (x, y)."""
        return self.nx * PATCH, self.ny * PATCH

    def world_to_cell(self, x: float, y: float) -> tuple[int, int]:
        """world2map: cell of point (x, y) m."""
        return (kernels.c_round((x - self.cx) / self.delta) + self.sx2,
                kernels.c_round((y - self.cy) / self.delta) + self.sy2)

    def cell_to_world(self, ix: float, iy: float) -> tuple[float, float]:
        """map2world: the point (m) cell (ix, iy) is centred on."""
        return (ix - self.sx2) * self.delta + self.cx, (iy - self.sy2) * self.delta + self.cy

    def is_inside(self, x: float, y: float) -> bool:
        """Whether point (x, y) m falls in a cell of the map."""
        ix, iy = self.world_to_cell(x, y)
        return ix >= 0 and iy >= 0 and (ix >> PATCH_MAGNITUDE) < self.nx \
            and (iy >> PATCH_MAGNITUDE) < self.ny

    def grow_to(self, bounds: tuple[float, float, float, float],
                enlarge: float = ENLARGE_STEP) -> Window | None:
        """computeActiveArea's resize: when ``bounds`` (xmin, ymin, xmax, ymax) m leave the map,
        enlarge it ``enlarge`` m beyond them on the sides they leave.

        Returns the patch window of the old table that the new one spans (see
        :meth:`ParticleMap.apply_window`), or None when nothing changed.
        """
        lxmin, lymin = self.cell_to_world(0, 0)
        lxmax, lymax = self.cell_to_world(self.size[0] - 1, self.size[1] - 1)
        xmin, ymin = min(bounds[0], lxmin), min(bounds[1], lymin)
        xmax, ymax = max(bounds[2], lxmax), max(bounds[3], lymax)
        if self.is_inside(xmin, ymin) and self.is_inside(xmax, ymax):
            return None
        xmin = lxmin if xmin >= lxmin else xmin - enlarge
        xmax = lxmax if xmax <= lxmax else xmax + enlarge
        ymin = lymin if ymin >= lymin else ymin - enlarge
        ymax = lymax if ymax <= lymax else ymax + enlarge
        return self.resize(xmin, ymin, xmax, ymax)

    def resize(self, xmin: float, ymin: float, xmax: float, ymax: float) -> Window:
        """Map::resize: the patch window covering the given world bounds becomes the map."""
        imin = self.world_to_cell(xmin, ymin)
        imax = self.world_to_cell(xmax, ymax)
        window = (int(math.floor(np.float32(imin[0]) / PATCH)),
                  int(math.floor(np.float32(imin[1]) / PATCH)),
                  int(math.ceil(np.float32(imax[0]) / PATCH)),
                  int(math.ceil(np.float32(imax[1]) / PATCH)))
        self.nx = window[2] - window[0]
        self.ny = window[3] - window[1]
        self.sx2 -= window[0] * PATCH
        self.sy2 -= window[1] * PATCH
        return window

    def copy(self) -> Geometry:
        """An independent copy."""
        return Geometry(self.cx, self.cy, self.delta, self.sx2, self.sy2, self.nx, self.ny)


class PatchPool:
    """Storage of all 32 x 32-cell patches (12 bytes a cell): hit-point sums, hit counts,
    reference counts.

    The arrays are zero-allocated, so the operating system commits their pages only when a patch
    is first used; free patches are reused lowest-first, which keeps the resident memory at the
    peak number of patches in use. A generous initial capacity therefore costs nothing and
    avoids growth copies; when exceeded, the pool doubles. ``nbytes`` is the reserved size.
    """

    def __init__(self, capacity: int = 256):
        capacity = max(int(capacity), 1)
        self.acc = np.zeros((capacity, PATCH * PATCH, 2), dtype=np.float32)
        self.hits = np.zeros((capacity, PATCH * PATCH), dtype=np.int32)
        self.ref = np.zeros(capacity, dtype=np.int32)
        self.free_stack = np.arange(capacity, dtype=np.int32)[::-1].copy()
        self.free_top = np.array([capacity], dtype=np.int64)

    @property
    def capacity(self) -> int:
        """Number of patch slots."""
        return len(self.ref)

    @property
    def in_use(self) -> int:
        """Number of patches some map refers to."""
        return self.capacity - int(self.free_top[0])

    @property
    def nbytes(self) -> int:
        """Bytes reserved by the pool arrays."""
        return self.acc.nbytes + self.hits.nbytes + self.ref.nbytes + self.free_stack.nbytes

    def grow(self, extra: int) -> None:
        """Make room for at least ``extra`` more free patches (capacity doubles, or more)."""
        old = self.capacity
        new = max(old + int(extra), 2 * old)
        acc = np.zeros((new, PATCH * PATCH, 2), dtype=np.float32)
        hits = np.zeros((new, PATCH * PATCH), dtype=np.int32)
        acc[:old] = self.acc
        hits[:old] = self.hits
        ref = np.zeros(new, dtype=np.int32)
        ref[:old] = self.ref
        top = int(self.free_top[0])
        stack = np.empty(new, dtype=np.int32)
        stack[:new - old] = np.arange(new - 1, old - 1, -1, dtype=np.int32)
        stack[new - old:new - old + top] = self.free_stack[:top]
        self.acc, self.hits, self.ref, self.free_stack = acc, hits, ref, stack
        self.free_top[0] = top + new - old


class ParticleMap:
    """One particle's map: its geometry and its patch table (shares patches through the pool)."""

    def __init__(self, pool: PatchPool, geometry: Geometry, table: np.ndarray | None = None):
        self.pool = pool
        self.geometry = geometry
        self.table = (np.full((geometry.nx, geometry.ny), -1, dtype=np.int32)
                      if table is None else table)

    def clone(self) -> ParticleMap:
        """A copy sharing every patch (only the table is copied)."""
        kernels.retain_table(self.table, self.pool.ref)
        return ParticleMap(self.pool, self.geometry.copy(), self.table.copy())

    def release(self) -> None:
        """Drop this map: patches no other map refers to go back to the pool."""
        kernels.release_table(self.table, self.pool.ref, self.pool.free_stack,
                              self.pool.free_top)
        self.table = np.full((0, 0), -1, dtype=np.int32)

    def apply_window(self, window: Window) -> None:
        """Re-index the table after :meth:`Geometry.resize` returned ``window``."""
        pxmin, pymin, pxmax, pymax = window
        new = np.full((pxmax - pxmin, pymax - pymin), -1, dtype=np.int32)
        x0, x1 = max(pxmin, 0), min(pxmax, self.table.shape[0])
        y0, y1 = max(pymin, 0), min(pymax, self.table.shape[1])
        if x1 > x0 and y1 > y0:
            new[x0 - pxmin:x1 - pxmin, y0 - pymin:y1 - pymin] = self.table[x0:x1, y0:y1]
        self.table = new

    def register(self, pose, ranges: np.ndarray, ca: np.ndarray, sa: np.ndarray,
                 max_range: float, usable: float) -> int:
        """Grow if needed, then add the scan's endpoint hits; returns patches taken from pool."""
        x, y, th = float(pose[0]), float(pose[1]), float(pose[2])
        bounds = kernels.scan_bounds(x, y, th, ranges, ca, sa, max_range, usable)
        window = self.geometry.grow_to(bounds)
        if window is not None:
            self.apply_window(window)
        g, pool = self.geometry, self.pool
        while True:
            status = kernels.register_hits(self.table, g.sx2, g.sy2, g.cx, g.cy, g.delta,
                                           pool.acc, pool.hits, pool.ref, pool.free_stack,
                                           pool.free_top, x, y, th, ranges, ca, sa, max_range,
                                           usable)
            if status >= 0:
                return status
            pool.grow(-status)

    def cell(self, ix: int, iy: int) -> tuple[int, float, float]:
        """(hits, mean x, mean y) of cell (ix, iy); hits 0 and NaN means when unknown."""
        if ix < 0 or iy < 0:
            return 0, math.nan, math.nan
        px, py = ix >> PATCH_MAGNITUDE, iy >> PATCH_MAGNITUDE
        if px >= self.table.shape[0] or py >= self.table.shape[1] or self.table[px, py] < 0:
            return 0, math.nan, math.nan
        pid = self.table[px, py]
        slot = ((ix & (PATCH - 1)) << PATCH_MAGNITUDE) | (iy & (PATCH - 1))
        n = int(self.pool.hits[pid, slot])
        if n == 0:
            return 0, math.nan, math.nan
        acc = self.pool.acc[pid, slot].astype(float)
        return n, acc[0] / n, acc[1] / n

    @property
    def allocated_patches(self) -> int:
        """Number of patches this map refers to."""
        return int(np.count_nonzero(self.table >= 0))
