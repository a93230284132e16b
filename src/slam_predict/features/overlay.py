"""Picture of the feature extraction on the plan: rooms, doorway cuts, topological graph,
Voronoi graph, traversal path and start pose.

Colours: obstacles dark grey, rooms tinted (fixed palette), doorway cuts black, topological
graph orange (thick), Voronoi edges blue and nodes red, traversal path green, start magenta.
Small plans are enlarged by an integer factor so that lines stay visible.
"""
from __future__ import annotations

import math
import os

import cv2
import numpy as np

from slam_predict.atomic import write_bytes
from slam_predict.errors import InputError

# BGR colours
PALETTE = np.array([(180, 119, 31), (14, 127, 255), (44, 160, 44), (40, 39, 214),
                    (189, 103, 148), (75, 86, 140), (194, 119, 227), (127, 127, 127),
                    (34, 189, 188), (207, 190, 23)], np.uint8)
OBSTACLE = (70, 70, 70)
TOPOLOGY = (0, 140, 255)
VORONOI_EDGE = (200, 120, 0)
VORONOI_NODE = (0, 0, 230)
PATH = (0, 170, 0)
START = (200, 0, 200)


def _pt(rc, scale: int):
    """OpenCV point (x, y) of pixel centre (row, col) in the enlarged picture."""
    return (int((rc[1] + 0.5) * scale), int((rc[0] + 0.5) * scale))


def render(ctx, max_side: int = 1600) -> np.ndarray:
    """BGR picture of a :class:`vector.Context` (computes what it draws if not done yet)."""
    world = ctx.world
    rows, cols = world.shape
    scale = max(1, min(4, max_side // max(rows, cols)))
    free = np.full((rows, cols, 3), 255, np.uint8)
    free[world.occupied] = OBSTACLE
    labels = ctx.rooms.labels
    tint = PALETTE[(labels - 1) % len(PALETTE)]
    room = labels > 0
    free[room] = (0.65 * free[room] + 0.35 * tint[room]).astype(np.uint8)
    img = cv2.resize(free, (cols * scale, rows * scale), interpolation=cv2.INTER_NEAREST)
    for a, b in ctx.rooms.cuts:
        cv2.line(img, _pt(a, scale), _pt(b, scale), (0, 0, 0), max(1, scale // 2))
    graph = ctx.voronoi
    for a, b in graph.edges:
        cv2.line(img, _pt(graph.rc[a], scale), _pt(graph.rc[b], scale), VORONOI_EDGE, 1)
    for rc in graph.rc:
        cv2.circle(img, _pt(rc, scale), max(1, scale), VORONOI_NODE, -1)
    path = ctx.traversal.path_rc
    if len(path) > 1:
        pts = np.array([_pt(rc, scale) for rc in path], np.int32).reshape(-1, 1, 2)
        cv2.polylines(img, [pts], False, PATH, max(1, scale))
    topo = ctx.topology
    for a, b in topo.edges:
        cv2.line(img, _pt(topo.points[a], scale), _pt(topo.points[b], scale), TOPOLOGY,
                 2 * max(1, scale))
    for rc in topo.points:
        cv2.circle(img, _pt(rc, scale), 3 * max(1, scale), TOPOLOGY, -1)
    _draw_start(img, world, scale)
    return img


def _draw_start(img: np.ndarray, world, scale: int) -> None:
    rc = world.world_to_cell(world.start_pose[:2])
    centre = _pt(rc, scale)
    radius = 5 * max(1, scale)
    yaw = float(world.start_pose[2])
    tip = (int(centre[0] + 2 * radius * math.cos(yaw)), int(centre[1] - 2 * radius * math.sin(yaw)))
    cv2.circle(img, centre, radius, START, 2)
    cv2.line(img, centre, tip, START, 2)


def write_overlay(ctx, out: os.PathLike | str, max_side: int | None = 1600) -> None:
    """Render and write the picture atomically as PNG; InputError when it cannot be written."""
    out = os.fspath(out)
    if not out.lower().endswith(".png"):
        raise InputError("overlay must be a .png file", out)
    ok, data = cv2.imencode(".png", render(ctx, max_side or 1600))
    if not ok:
        raise InputError("PNG encoder failed", out)
    try:
        write_bytes(out, data.tobytes())
    except OSError as exc:
        raise InputError(f"cannot write overlay ({exc.strerror or exc})", out) from None
