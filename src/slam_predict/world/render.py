"""Render a World as a picture: free/occupied space, start pose, scale bar, ground truth.

Drawn in world metres (x right, y up) with matplotlib's Agg backend (no display needed):
free space white, obstacles dark grey, the start pose as a red arrow, a scale bar, and — when
the World has them — ground-truth rooms (outlined, labelled) and doors (green segments).
"""
from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from slam_predict.atomic import atomic_path
from slam_predict.errors import InputError
from slam_predict.world.model import World

FORMATS = (".png", ".pdf", ".svg", ".jpg")


def nice_length(max_length: float) -> float:
    """The largest 1/2/5·10^k length ≤ ``max_length`` (m), for scale bars."""
    if max_length <= 0:
        return 0.0
    exponent = math.floor(math.log10(max_length))
    for mantissa in (5, 2, 1):
        value = mantissa * 10.0 ** exponent
        if value <= max_length * (1 + 1e-12):
            return value
    return 10.0 ** exponent  # pragma: no cover - mantissa 1 always fits


def extent(world: World):
    """(left, right, bottom, top) of the bitmap in world metres (matplotlib's order)."""
    xmin, ymin, xmax, ymax = world.extent
    return xmin, xmax, ymin, ymax


def _draw_ground_truth(ax, world: World) -> None:
    import matplotlib

    cmap = matplotlib.colormaps["tab20"]
    for k, room in enumerate(world.rooms):
        poly = np.asarray(room.polygon, dtype=float)
        if poly.ndim != 2 or len(poly) < 3:
            continue
        closed = np.vstack([poly, poly[:1]])
        ax.fill(poly[:, 0], poly[:, 1], color=cmap(k % 20), alpha=0.25, linewidth=0)
        ax.plot(closed[:, 0], closed[:, 1], color=cmap(k % 20), linewidth=0.8)
        if room.label:
            cx, cy = poly.mean(axis=0)
            ax.text(cx, cy, room.label, fontsize=5, ha="center", va="center", color="0.2")
    for door in world.doors:
        seg = np.asarray(door.segment, dtype=float)
        ax.plot(seg[:, 0], seg[:, 1], color="tab:green", linewidth=2.0, solid_capstyle="butt")


def _draw_start(ax, world: World) -> None:
    x, y, yaw = (float(v) for v in world.start_pose)
    length = max(world.robot.footprint_side * 2.0, 0.03 * max(world.size_m))
    ax.plot([x], [y], "o", color="tab:red", markersize=4)
    ax.annotate("", xy=(x + length * math.cos(yaw), y + length * math.sin(yaw)), xytext=(x, y),
                arrowprops=dict(arrowstyle="-|>", color="tab:red", linewidth=1.5))


def _draw_scale_bar(ax, world: World) -> None:
    left, right, bottom, top = extent(world)
    length = nice_length((right - left) / 4.0)
    x0 = left + 0.04 * (right - left)
    y0 = bottom + 0.04 * (top - bottom)
    ax.plot([x0, x0 + length], [y0, y0], color="tab:blue", linewidth=3, solid_capstyle="butt")
    label = f"{length:g} m" if length >= 1 else f"{length * 100:g} cm"
    ax.text(x0 + length / 2.0, y0 + 0.015 * (top - bottom), label, color="tab:blue",
            ha="center", va="bottom", fontsize=8)


def render_world(world: World, out: os.PathLike | str, dpi: int = 150,
                 title: str | None = None) -> Path:
    """Draw ``world`` to the image file ``out`` (.png, .pdf, .svg or .jpg), atomically."""
    out = Path(out)
    if out.suffix.lower() not in FORMATS:
        raise InputError(f"picture format '{out.suffix}' not supported (use one of "
                         f"{', '.join(FORMATS)})", out)
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.figure import Figure

    width, height = world.size_m
    aspect = height / width
    fig = Figure(figsize=(8.0, max(2.5, min(16.0, 8.0 * aspect)) + 0.6))
    ax = fig.add_subplot(1, 1, 1)
    image = np.where(world.occupied, 0.25, 1.0)
    ax.imshow(image, cmap="gray", vmin=0.0, vmax=1.0, extent=extent(world),
              interpolation="nearest", origin="upper")
    _draw_ground_truth(ax, world)
    _draw_start(ax, world)
    _draw_scale_bar(ax, world)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    rows, cols = world.shape
    ax.set_title(title or f"{world.name}: {cols} x {rows} px at {world.resolution:g} m/px, "
                 f"free {world.free_area_m2:.1f} m²", fontsize=9)
    ax.set_aspect("equal")
    fig.tight_layout()
    with atomic_path(out, suffix=out.suffix) as tmp:
        fig.savefig(tmp, dpi=dpi, format=out.suffix.lower().lstrip(".").replace("jpg", "jpeg"))
    return out
