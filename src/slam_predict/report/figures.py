"""The report's figures (matplotlib Agg), returned as PNG bytes.

Map overlay frames: the SLAM map is a map_server image (row 0 = top) whose lower-left pixel
corner sits at the YAML ``origin`` (x, y, yaw) of the map frame. The SLAM trajectory is in the
map frame; the ground truth is in the world frame and is brought into the map frame with
world_T_map = gt₀ ⊕ slam₀⁻¹ (both start at the same instant). Points are then expressed in the
origin's frame, where pixel (row r, col c) covers x ∈ [c·res, (c+1)·res],
y ∈ [(H−r−1)·res, (H−r)·res] (m).
"""
from __future__ import annotations

import io
from collections.abc import Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from slam_predict.formats.mapserver import FREE, OCCUPIED, MapServerMap  # noqa: E402
from slam_predict.geometry import compose, inverse, ominus, world_T_map  # noqa: E402

CROP_MARGIN_M = 1.0
DPI = 100
MAX_DISPLAY_PX = 1400


def to_origin_frame(points_map: np.ndarray, origin: Sequence[float]) -> np.ndarray:
    """Map-frame poses (n, 3) expressed in the frame of the map image's lower-left corner."""
    return ominus(np.asarray(points_map, float), np.asarray(origin, float))


def image_extent(shape: tuple[int, int], resolution: float) -> tuple[float, float, float, float]:
    """(left, right, bottom, top) of the image in the origin frame (m), for imshow."""
    rows, cols = shape
    return 0.0, cols * resolution, 0.0, rows * resolution


def known_box(image: np.ndarray, resolution: float) -> tuple[float, float, float, float]:
    """(x0, x1, y0, y1) in the origin frame (m) of the known (free or occupied) pixels."""
    known = (image >= FREE) | (image <= OCCUPIED)
    if not known.any():
        return image_extent(image.shape, resolution)
    rows, cols = np.flatnonzero(known.any(1)), np.flatnonzero(known.any(0))
    height = image.shape[0]
    return (cols[0] * resolution, (cols[-1] + 1) * resolution,
            (height - rows[-1] - 1) * resolution, (height - rows[0]) * resolution)


def view_box(image: np.ndarray, resolution: float, points: np.ndarray):
    """(x0, x1, y0, y1) (origin frame, m) holding the known map and the points, plus a margin."""
    x0, x1, y0, y1 = known_box(image, resolution)
    low, high = points[:, :2].min(axis=0), points[:, :2].max(axis=0)
    margin = CROP_MARGIN_M
    return (min(x0, low[0]) - margin, max(x1, high[0]) + margin,
            min(y0, low[1]) - margin, max(y1, high[1]) + margin)


def crop_for_display(image: np.ndarray, resolution: float, box: tuple[float, float, float, float],
                     max_pixels: int = MAX_DISPLAY_PX, fill=FREE):
    """The part of a map image inside ``box`` (x0, x1, y0, y1, origin frame, m), reduced by
    block minimum (dark walls survive) to at most ``max_pixels`` per side, padded with
    ``fill``; returns (image, extent (left, right, bottom, top) in the origin frame)."""
    height, width = image.shape
    x0, x1, y0, y1 = box
    c0 = int(np.clip(np.floor(x0 / resolution), 0, width))
    c1 = int(np.clip(np.ceil(x1 / resolution), c0, width))
    r0 = int(np.clip(np.floor(height - y1 / resolution), 0, height))
    r1 = int(np.clip(np.ceil(height - y0 / resolution), r0, height))
    crop = image[r0:r1, c0:c1]
    step = max(1, int(np.ceil(max(crop.shape + (1,)) / max_pixels)))
    if step > 1:
        rows, cols = -(-crop.shape[0] // step) * step, -(-crop.shape[1] // step) * step
        padded = np.full((rows, cols), fill, dtype=crop.dtype)
        padded[:crop.shape[0], :crop.shape[1]] = crop
        crop = padded.reshape(rows // step, step, cols // step, step).min(axis=(1, 3))
        c1, r1 = c0 + cols, r0 + rows
    extent = (c0 * resolution, c1 * resolution, (height - r1) * resolution,
              (height - r0) * resolution)
    return crop, extent


def png_bytes(fig) -> bytes:
    """Render and close a figure."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=DPI)
    plt.close(fig)
    return buffer.getvalue()


def display_levels(image: np.ndarray) -> np.ndarray:
    """Grey levels of map_saver values for display: free 1 (white), occupied 0 (black),
    unknown 0.8 (grey)."""
    shown = np.full(image.shape, 0.8)
    shown[image >= FREE] = 1.0
    shown[image <= OCCUPIED] = 0.0
    return shown


def map_overlay(grid: MapServerMap, ground_truth: np.ndarray, slam: np.ndarray,
                title: str) -> bytes:
    """PNG of :func:`map_overlay_figure`."""
    return png_bytes(map_overlay_figure(grid, ground_truth, slam, title))


def map_overlay_figure(grid: MapServerMap, ground_truth: np.ndarray, slam: np.ndarray,
                       title: str):
    """The final SLAM map with the ground-truth (world → map frame) and SLAM paths on it;
    axes in the map frame (m) when the map origin has no yaw."""
    origin = np.asarray(grid.origin, float)
    gt_map = compose(inverse(world_T_map(ground_truth[0], slam[0])), ground_truth)
    gt_xy = to_origin_frame(gt_map, origin)[:, :2]
    slam_xy = to_origin_frame(slam, origin)[:, :2]
    raw = 255 - grid.image if grid.negate else grid.image
    shift = origin[:2] if abs(origin[2]) < 1e-12 else np.zeros(2)  # label axes in map frame
    x0, x1, y0, y1 = view_box(raw, grid.resolution, np.vstack([gt_xy, slam_xy]))
    aspect = (y1 - y0) / max(x1 - x0, 1e-9)
    width = 7.0
    fig, ax = plt.subplots(figsize=(width, float(np.clip(width * aspect, 3.0, 10.0)) + 0.6))
    crop, (left, right, bottom, top) = crop_for_display(raw, grid.resolution, (x0, x1, y0, y1))
    ax.imshow(display_levels(crop), cmap="gray", vmin=0, vmax=1, origin="upper",
              interpolation="nearest",
              extent=(left + shift[0], right + shift[0], bottom + shift[1], top + shift[1]))
    ax.plot(gt_xy[:, 0] + shift[0], gt_xy[:, 1] + shift[1], "-", color="tab:green", lw=1.2,
            label="ground truth")
    ax.plot(slam_xy[:, 0] + shift[0], slam_xy[:, 1] + shift[1], "-", color="tab:red", lw=1.0,
            label="SLAM estimate")
    ax.plot(gt_xy[0, 0] + shift[0], gt_xy[0, 1] + shift[1], "o", color="black", ms=5,
            label="start")
    ax.set_xlim(x0 + shift[0], x1 + shift[0])
    ax.set_ylim(y0 + shift[1], y1 + shift[1])
    ax.set_aspect("equal")
    frame = "map frame" if abs(origin[2]) < 1e-12 else "frame of the map origin"
    ax.set_xlabel(f"x [m] ({frame})")
    ax.set_ylabel(f"y [m] ({frame})")
    ax.set_title(title, fontsize=10)
    ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    return fig


def predicted_vs_measured(points: dict[str, list[dict]], units: dict[str, str],
                          labels: dict[str, str], title: str) -> bytes:
    """One panel per component that has points (2×2 for four, side by side for fewer):
    predicted (with interval bars) vs measured, y = x line.

    ``points[component]`` lists dicts with ``world``, ``measured``, ``value``, ``low``, ``high``.
    """
    points = {c: items for c, items in points.items() if items}
    n = len(points)
    cols = 2 if n == 4 else n
    rows = 2 if n == 4 else 1
    fig, axes = plt.subplots(rows, cols, figsize=(4.75 * cols, 4 * rows + 0.5), squeeze=False)
    for ax, (component, items) in zip(axes.ravel(), points.items(), strict=False):
        measured = np.array([p["measured"] for p in items])
        value = np.array([p["value"] for p in items])
        low = np.array([p["low"] for p in items])
        high = np.array([p["high"] for p in items])
        ax.errorbar(measured, value, yerr=[value - low, high - value], fmt="o", color="tab:blue",
                    ecolor="tab:blue", alpha=0.8, capsize=3, label="prediction (interval)")
        top = float(max(measured.max(), high.max())) * 1.1 or 1.0
        ax.plot([0, top], [0, top], "--", color="grey", lw=1, label="predicted = measured")
        for p in items:
            ax.annotate(p["world"], (p["measured"], p["value"]), fontsize=7,
                        xytext=(3, 3), textcoords="offset points")
        unit = units[component]
        ax.set_xlim(0, top)
        ax.set_ylim(0, top)
        ax.set_xlabel(f"measured {labels[component]} [{unit}]")
        ax.set_ylabel(f"predicted [{unit}]")
        ax.set_title(labels[component], fontsize=10)
        ax.legend(fontsize=7, loc="upper left")
    fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    return png_bytes(fig)


def partial_dependence(curves: dict[str, dict], ylabel: str, title: str) -> bytes:
    """One panel per robot input (two rows for four or more): the model's average prediction
    against the input, the training range shaded, the training configurations as ticks on the
    x axis and an optional cap line (GMapping's maxUrange on the range).

    ``curves[input]``: ``grid``, ``values`` (same length), ``xlabel`` (with unit),
    ``trained`` (low, high), ``configs`` (values of the configurations), ``cap`` (x or None).
    """
    n = len(curves)
    rows = 2 if n >= 4 else 1
    cols = -(-n // rows)
    fig, axes = plt.subplots(rows, cols, figsize=(4.75 * cols, 3.6 * rows + 0.5), squeeze=False)
    for ax in axes.ravel()[n:]:
        ax.set_visible(False)
    for ax, (name, c) in zip(axes.ravel(), curves.items(), strict=False):
        ax.axvspan(*c["trained"], color="tab:green", alpha=0.12, label="training range")
        ax.plot(c["grid"], c["values"], "-", color="tab:blue", lw=1.6,
                label="average prediction")
        ax.plot(c["configs"], np.full(len(c["configs"]), 0.0), "|", color="black", ms=10,
                transform=ax.get_xaxis_transform(), label="training configurations")
        if c.get("cap") is not None:
            ax.axvline(c["cap"], ls="--", color="grey", lw=1,
                       label="GMapping maxUrange (a longer laser is this input)")
        ax.set_xlabel(c["xlabel"])
        ax.set_ylabel(ylabel)
        ax.set_title(name, fontsize=10)
        ax.legend(fontsize=7, loc="best")
    fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    return png_bytes(fig)
