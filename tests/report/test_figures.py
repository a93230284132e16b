"""Map overlay frames against brute-force references, and the figures' pixels."""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from slam_predict.formats.mapserver import FREE, OCCUPIED, UNKNOWN, MapServerMap  # noqa: E402
from slam_predict.geometry import compose  # noqa: E402
from slam_predict.report import figures  # noqa: E402

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("yaw", [0.0, 0.3, -2.0])
def test_origin_frame_matches_nearest_pixel_centre(yaw):
    """A map-frame point lies in pixel (row, col) iff that pixel's centre (computed forward
    from the origin) is the nearest centre — checked against every pixel."""
    rng = np.random.default_rng(1)
    height, width, res = 30, 40, 0.25
    origin = np.array([-3.0, 2.0, yaw])
    rows, cols = np.mgrid[0:height, 0:width]
    local = np.column_stack([(cols.ravel() + 0.5) * res, (height - rows.ravel() - 0.5) * res,
                             np.zeros(rows.size)])
    centres = compose(origin, local)[:, :2]                     # forward: pixel → map frame
    picks = rng.integers(0, rows.size, 25)
    jitter = np.column_stack([rng.uniform(-0.45 * res, 0.45 * res, (25, 2)), np.zeros(25)])
    points = compose(origin, local[picks] + jitter)[:, :2]      # inside the picked pixels
    xy = figures.to_origin_frame(np.column_stack([points, np.zeros(25)]), origin)[:, :2]
    col, row = np.floor(xy[:, 0] / res), np.floor(height - xy[:, 1] / res)
    nearest = np.argmin(((points[:, None, :] - centres[None]) ** 2).sum(-1), axis=1)
    assert np.array_equal(row * width + col, nearest)
    assert np.array_equal(nearest, picks)


def block_min_reference(image, step):
    out = np.empty((-(-image.shape[0] // step), -(-image.shape[1] // step)), image.dtype)
    for i in range(out.shape[0]):
        for j in range(out.shape[1]):
            out[i, j] = image[i * step:(i + 1) * step, j * step:(j + 1) * step].min()
    return out


@pytest.mark.parametrize("max_pixels", [1000, 7])
def test_crop_keeps_pixels_in_place(max_pixels):
    rng = np.random.default_rng(2)
    image = rng.choice(np.array([OCCUPIED, UNKNOWN, FREE], np.uint8), size=(50, 60))
    res = 0.1
    crop, (left, right, bottom, top) = figures.crop_for_display(image, res, (1.23, 4.5, 0.7, 3.1),
                                                                max_pixels=max_pixels)
    step = round((right - left) / res / crop.shape[1])
    assert max(crop.shape) <= max(max_pixels, 1) or step == 1
    assert (top - bottom) == pytest.approx(crop.shape[0] * step * res)
    col0, row0 = round(left / res), round(50 - top / res)
    assert col0 <= 12 and row0 <= 50 - 31 and right >= 4.5 - 1e-9 and bottom <= 0.7 + 1e-9
    window = image[row0:, col0:][:crop.shape[0] * step, :crop.shape[1] * step]
    expected = block_min_reference(window, step)
    assert np.array_equal(crop[:expected.shape[0], :expected.shape[1]], expected)


def fake_map():
    """A map_server image (row 0 = top): all free, one occupied 4×4 block, origin (-2, -1)."""
    image = np.full((40, 60), FREE, np.uint8)
    image[8:12, 44:48] = OCCUPIED          # rows from the top
    return MapServerMap(image=image, resolution=0.1, origin=(-2.0, -1.0, 0.0))


def test_overlay_draws_the_map_at_its_origin_and_resolution():
    grid = fake_map()
    slam = np.column_stack([np.linspace(0, 1, 20), np.zeros(20), np.zeros(20)])
    gt = compose(np.array([5.0, 5.0, 1.0]), slam)
    fig = figures.map_overlay_figure(grid, gt, slam, "test")
    ax = fig.axes[0]
    fig.canvas.draw()
    pixels = np.asarray(fig.canvas.buffer_rgba())[..., :3].astype(int)
    # block centre in the map frame: x = -2 + 46 · 0.1, y = -1 + (40 − 10) · 0.1
    wall = ax.transData.transform((-2.0 + 4.6, -1.0 + 3.0))
    free = ax.transData.transform((-2.0 + 2.0, -1.0 + 3.0))
    height = pixels.shape[0]
    at = lambda p: pixels[int(round(height - p[1])), int(round(p[0]))]  # noqa: E731
    assert at(wall).max() < 60            # black wall
    assert at(free).min() > 230           # white free space
    plt.close(fig)


def test_figures_are_png():
    grid = fake_map()
    slam = np.column_stack([np.linspace(0, 1, 20), np.zeros(20), np.zeros(20)])
    assert figures.map_overlay(grid, slam, slam, "t").startswith(PNG_MAGIC)
    item = {"world": "w", "measured": 0.1, "value": 0.12, "low": 0.05, "high": 0.2}
    points = {"trans_mean": [item], "trans_std": [], "rot_mean": [item], "rot_std": [item]}
    png = figures.predicted_vs_measured(points, {k: "m" for k in points},
                                        {k: k for k in points}, "t")
    assert png.startswith(PNG_MAGIC)
