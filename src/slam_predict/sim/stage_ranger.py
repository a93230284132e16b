"""Stage 4.1.1's laser as a simulator option (``SimConfig.ranger_model = "stage"``).

A :class:`StageGrid` is the cell grid Stage would build from a World's bitmap: the bitmap is cut
into rectangles as Stage cuts a floor-plan image, the rectangles are stretched to the floor
plan's size (the World's extent) and centred on its origin, and their outlines are drawn into
cells of ``resolution`` m (plus the four 0.01-pixel ``boundary 1`` strips our .world writer asks
for). :meth:`StageGrid.scan` casts a scan with Stage's ray walk, the robot's square body marking
its regions as Stage's own blocks do, at the scan pose and (Stage's other grid layer) at the pose
one update earlier. See :mod:`slam_predict.sim.stage_raytrace_kernels` for
the Stage behaviour reproduced.

Collisions are not affected: the simulator keeps checking them on the World's bitmap.
"""
from __future__ import annotations

import math
import weakref

import numpy as np

from slam_predict.sim import stage_raytrace_kernels as k

DEFAULT_RESOLUTION = 0.025  # m: the seed study's .world files
BOUNDARY_EPSILON = 0.01  # block units (pixels): Stage's boundary strip width

_GRID_CACHE: dict = {}  # (id(bitmap), ...) → (weak reference to the bitmap, its StageGrid)


def stage_resolution(world, configured: float | None) -> float:
    """The Stage raytrace cell (m): ``configured``, else the World's .world ``resolution``,
    else :data:`DEFAULT_RESOLUTION`."""
    if configured is not None:
        return float(configured)
    stage = (getattr(world, "provenance", None) or {}).get("stage") or {}
    value = stage.get("resolution")
    return float(value) if value else DEFAULT_RESOLUTION


def rect_corners(rects: np.ndarray, boundary: bool) -> np.ndarray:
    """Float (k, 4, 2) block corners (pixel units, y up) of Stage rectangles (x, y, w, h), in
    Stage's order (x, y), (x+w, y), (x+w, y+h), (x, y+h); with the boundary strips appended
    when ``boundary`` (their extent is the rectangles' bounding box)."""
    r = np.asarray(rects, dtype=float).reshape(-1, 4)
    if boundary and len(r):
        lo_x, lo_y = r[:, 0].min(), r[:, 1].min()
        hi_x, hi_y = (r[:, 0] + r[:, 2]).max(), (r[:, 1] + r[:, 3]).max()
        w, h, e = hi_x - lo_x, hi_y - lo_y, BOUNDARY_EPSILON
        strips = np.array([[lo_x, lo_y, e, h], [lo_x, lo_y, w, e], [lo_x, hi_y - e, w, e],
                           [hi_x - e, lo_y, e, h]])
        r = np.vstack([r, strips])
    x, y, w, h = r[:, 0], r[:, 1], r[:, 2], r[:, 3]
    xs = np.stack([x, x + w, x + w, x], axis=1)
    ys = np.stack([y, y, y + h, y + h], axis=1)
    return np.stack([xs, ys], axis=2)


def corners_to_cells(corners: np.ndarray, size: tuple[float, float], centre: tuple[float, float],
                     ppm: float) -> np.ndarray:
    """int64 cells of block corners (pixel units) of a floor plan stretched to ``size`` (W, H
    m) and centred on ``centre`` (x, y m), unrotated: Stage's arithmetic, step by step."""
    xs, ys = corners[..., 0], corners[..., 1]
    min_x, max_x, min_y, max_y = xs.min(), xs.max(), ys.min(), ys.max()
    bg_w, bg_h = max_x - min_x, max_y - min_y
    off_x, off_y = min_x + bg_w / 2.0, min_y + bg_h / 2.0
    mx = (xs - off_x) * (size[0] / bg_w)
    my = (ys - off_y) * (size[1] / bg_h)
    gx = centre[0] + mx * 1.0 - my * 0.0  # Pose addition at angle 0
    gy = centre[1] + mx * 0.0 + my * 1.0
    return np.stack([np.floor(gx * ppm), np.floor(gy * ppm)], axis=-1).astype(np.int64)


def body_cells(x: float, y: float, yaw: float, side: float, ppm: float) -> np.ndarray:
    """int64 (1, 4, 2) cells of the corners of a robot's default square block (side m) at
    (x, y, yaw)."""
    half = np.array([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]]) * side
    c, s = math.cos(yaw), math.sin(yaw)
    gx = x + half[:, 0] * c - half[:, 1] * s
    gy = y + half[:, 0] * s + half[:, 1] * c
    return np.stack([np.floor(gx * ppm), np.floor(gy * ppm)], axis=-1).astype(np.int64)[None]


class StageGrid:
    """Stage's cell grid of a World (see the module docstring).

    Args:
        world: the World (its bitmap is the floor-plan image, its extent the model size).
        resolution: Stage cell size, m.
        boundary: add Stage's ``boundary 1`` strips.
    """

    def __init__(self, world, resolution: float, boundary: bool = True):
        self.resolution = float(resolution)
        self.ppm = 1.0 / self.resolution
        xmin, ymin, xmax, ymax = world.extent
        rects = k.cut_rects(np.ascontiguousarray(world.occupied, dtype=bool))
        if len(rects) == 0:
            raise ValueError(f"{world.name}: the bitmap has no obstacle")
        corners = rect_corners(rects, boundary)
        cells = corners_to_cells(corners, (xmax - xmin, ymax - ymin),
                                 tuple(float(v) for v in world.origin), self.ppm)
        margin = 2 * k.REGION_WIDTH
        self.x0 = ((int(cells[..., 0].min()) >> k.RBITS) << k.RBITS) - margin
        self.y0 = ((int(cells[..., 1].min()) >> k.RBITS) << k.RBITS) - margin
        x1 = ((int(cells[..., 0].max()) >> k.RBITS) + 1 << k.RBITS) + margin
        y1 = ((int(cells[..., 1].max()) >> k.RBITS) + 1 << k.RBITS) + margin
        counts = np.zeros((y1 - self.y0, x1 - self.x0), dtype=np.int32)
        k.map_polys(counts, self.x0, self.y0, cells)
        self.occupied = counts > 0
        self.regions = k.region_counts(counts, self.x0, self.y0)

    def regions_with_body(self, poses, side: float) -> np.ndarray:
        """Region counts with a robot body (square, side m) at each of ``poses`` (x, y, yaw)
        added."""
        regions = self.regions.copy()
        if side > 0:
            for x, y, yaw in poses:
                self._add_body(regions, float(x), float(y), float(yaw), side)
        return regions

    def _add_body(self, regions: np.ndarray, x: float, y: float, yaw: float,
                  side: float) -> None:
        cells = body_cells(x, y, yaw, side, self.ppm)
        bx0 = (int(cells[..., 0].min()) >> k.RBITS) << k.RBITS
        by0 = (int(cells[..., 1].min()) >> k.RBITS) << k.RBITS
        bx1 = ((int(cells[..., 0].max()) >> k.RBITS) + 1) << k.RBITS
        by1 = ((int(cells[..., 1].max()) >> k.RBITS) + 1) << k.RBITS
        body = np.zeros((by1 - by0, bx1 - bx0), dtype=np.int32)
        k.map_polys(body, bx0, by0, cells)
        counts = k.region_counts(body, bx0, by0)
        r0 = (by0 - self.y0) >> k.RBITS
        c0 = (bx0 - self.x0) >> k.RBITS
        for (r, c), n in np.ndenumerate(counts):
            if n and 0 <= r0 + r < regions.shape[0] and 0 <= c0 + c < regions.shape[1]:
                regions[r0 + r, c0 + c] += n

    def scan(self, robot_pose, laser_pose, fov: float, samples: int, range_max: float,
             body_side: float, out: np.ndarray | None = None,
             previous_pose=None) -> np.ndarray:
        """float32 ranges (m) of a Stage scan: laser at world ``laser_pose`` (x, y, yaw), beams
        from −fov/2 to +fov/2 (rad), the robot's body (square, ``body_side`` m) at
        ``robot_pose`` and, when given, at ``previous_pose`` (Stage's other layer: the pose
        one update earlier). A beam hitting nothing reads ``range_max``."""
        if out is None:
            out = np.empty(int(samples), dtype=np.float32)
        poses = [robot_pose] if previous_pose is None else [robot_pose, previous_pose]
        regions = self.regions_with_body(poses, float(body_side))
        start = -fov / 2.0 if samples > 1 else 0.0
        step = fov / max(int(samples) - 1, 1)
        a0 = _normalize(float(laser_pose[2]) + start)
        return k.stage_scan(self.occupied, regions, self.x0, self.y0, self.ppm,
                            float(laser_pose[0]), float(laser_pose[1]), a0, step,
                            float(range_max), out)


def _normalize(a: float) -> float:
    """Stage's angle normalisation into [−π, π]."""
    while a < -math.pi:
        a += 2.0 * math.pi
    while a > math.pi:
        a -= 2.0 * math.pi
    return a


def cached_stage_grid(world, resolution: float) -> StageGrid:
    """The :class:`StageGrid` of ``world`` at ``resolution``, built once per bitmap array while
    it lives (a bitmap must not be modified in place)."""
    occ = world.occupied
    key = (id(occ), float(resolution), tuple(world.extent))
    entry = _GRID_CACHE.get(key)
    if entry is not None and entry[0]() is occ:
        return entry[1]
    grid = StageGrid(world, resolution)
    _GRID_CACHE[key] = (weakref.ref(occ), grid)
    weakref.finalize(occ, _GRID_CACHE.pop, key, None)
    return grid


def warmup() -> None:
    """Compile the kernels on a tiny world (fills numba's cache)."""
    from slam_predict.world.model import World

    occ = np.ones((40, 40), dtype=bool)
    occ[2:38, 2:38] = False
    grid = StageGrid(World("warmup", occ, 0.05), 0.025)
    grid.scan((0.1, 0.1, 0.2), (0.1, 0.1, 0.2), 4.0, 9, 5.0, 0.3)
