"""Bitmap floor plans (PNG/PGM, 1/8/16-bit, grey or colour) → occupancy.

The threshold rule (one rule for every image):
1. Convert to 8-bit grey: 16-bit values are divided by 257; colour uses ITU-R 601 luma;
   an alpha channel is composited onto black (transparent = obstacle).
2. A pixel is free iff its grey value ≥ ``free_threshold`` (default 250, the rule of the ipa
   room-segmentation maps; anti-aliased wall edges and grey "outside" fills count as obstacle).
3. Free space 4-connected to the image border is outside the building: it becomes obstacle
   (with a warning). An image with nothing left is not an enclosed building.

Size guard: before decoding, :func:`read_grey` reads the image size from its header (Pillow
reads headers without decoding) and refuses an image of more than the pixel limit
(:data:`DEFAULT_MAX_PIXELS`, 50 M px; :func:`pixel_limit` changes it, the CLI's
``--max-pixels``): a 20000 x 20000 px plan needs about 13 GB (:data:`BYTES_PER_PIXEL`) and
minutes of feature extraction.
"""
from __future__ import annotations

import contextlib
import contextvars
import logging
import os
from collections.abc import Iterator

import cv2
import numpy as np
from scipy import ndimage

from slam_predict.errors import InputError, require_file

LOG = logging.getLogger(__name__)
FREE_THRESHOLD = 250
DEFAULT_MAX_PIXELS = 50_000_000
BYTES_PER_PIXEL = 33  # peak memory of loading + feature extraction per image pixel (bench)
_MAX_PIXELS = contextvars.ContextVar("max_pixels", default=DEFAULT_MAX_PIXELS)


@contextlib.contextmanager
def pixel_limit(max_pixels: int | None) -> Iterator[None]:
    """Within the block, :func:`read_grey` refuses images above ``max_pixels`` (None: the
    default limit)."""
    if max_pixels is not None and max_pixels < 1:
        raise InputError(f"--max-pixels must be ≥ 1, got {max_pixels}")
    token = _MAX_PIXELS.set(DEFAULT_MAX_PIXELS if max_pixels is None else int(max_pixels))
    try:
        yield
    finally:
        _MAX_PIXELS.reset(token)


def header_size(path: str) -> tuple[int, int] | None:
    """(width, height) in px from the image header, without decoding; None if Pillow cannot
    identify the format (the decoder then has the last word)."""
    import warnings

    from PIL import Image

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Image.DecompressionBombWarning)  # our guard decides
        try:
            with Image.open(path) as image:  # lazy: reads the header only
                return image.size
        except Image.DecompressionBombError:  # Pillow's own guard, raised before decoding
            pass
        except Exception:  # noqa: BLE001 — unidentified or corrupt: the decoder reports it
            return None
        old, Image.MAX_IMAGE_PIXELS = Image.MAX_IMAGE_PIXELS, None
        try:
            with Image.open(path) as image:
                return image.size
        finally:
            Image.MAX_IMAGE_PIXELS = old


def check_pixel_count(path: str) -> None:
    """InputError when the image's header announces more pixels than the current limit."""
    size = header_size(path)
    limit = _MAX_PIXELS.get()
    if size is None or size[0] * size[1] <= limit:
        return
    pixels = size[0] * size[1]
    raise InputError(f"image is {size[0]} x {size[1]} px ({pixels / 1e6:.0f} M px, about "
                     f"{pixels * BYTES_PER_PIXEL / 1e9:.1f} GB to process), more than the "
                     f"limit of {limit / 1e6:g} M px: downscale it, or raise the limit with "
                     f"--max-pixels {pixels}", path)


def read_grey(path: os.PathLike | str) -> np.ndarray:
    """Read an image as 8-bit grey (rows, cols); InputError when unreadable or corrupt, or
    larger than the pixel limit (checked from the header, before decoding)."""
    path = require_file(path, "image")
    check_pixel_count(path)
    raw = cv2.imread(path, cv2.IMREAD_UNCHANGED)
    if raw is None or raw.size == 0:
        raise InputError("cannot read image (corrupt or unsupported format)", path)
    if raw.dtype == np.uint16:
        raw = (raw.astype(np.uint32) // 257).astype(np.uint8)
    elif raw.dtype == bool:
        raw = raw.astype(np.uint8) * 255
    elif raw.dtype != np.uint8:
        raise InputError(f"unsupported pixel type {raw.dtype}", path)
    if raw.ndim == 2:
        return raw
    channels = raw.shape[2]
    if channels == 1:
        return raw[:, :, 0]
    if channels == 2:  # grey + alpha (OpenCV returns LA as 2 channels only for some codecs)
        return (raw[:, :, 0].astype(np.uint16) * raw[:, :, 1] // 255).astype(np.uint8)
    grey = cv2.cvtColor(raw[:, :, :3], cv2.COLOR_BGR2GRAY)
    if channels == 4:
        grey = (grey.astype(np.uint16) * raw[:, :, 3] // 255).astype(np.uint8)
    return grey


def free_mask(grey: np.ndarray, free_threshold: int = FREE_THRESHOLD) -> np.ndarray:
    """True where a grey pixel is free space (≥ ``free_threshold``)."""
    return grey >= free_threshold


def remove_outside(free: np.ndarray, source: str | None = None) -> np.ndarray:
    """Free space without the parts 4-connected to the image border (the outside).

    Raises InputError when the image has no free space, or when no free space is enclosed.
    """
    if not free.any():
        raise InputError("image has no free space", source)
    labels, _ = ndimage.label(free)
    border = np.unique(np.concatenate([labels[0], labels[-1], labels[:, 0], labels[:, -1]]))
    border = border[border > 0]
    outside = np.isin(labels, border)
    if outside.any():
        inside = free & ~outside
        if not inside.any():
            raise InputError("no enclosed building: all free space touches the image border",
                             source)
        LOG.warning("%s: %d free px connected to the image border treated as outside",
                    source or "image", int(outside.sum()))
        return inside
    return free


def load_occupancy(path: os.PathLike | str, free_threshold: int = FREE_THRESHOLD) -> np.ndarray:
    """Occupancy (True = obstacle/outside) of a floor-plan image by the threshold rule."""
    grey = read_grey(path)
    return ~remove_outside(free_mask(grey, free_threshold), os.fspath(path))


def _source_ranges(n_src: int, n_new: int):
    """For each target pixel along one axis, the half-open range [lo, hi) of source pixels.

    Downsampling (a target pixel spans ≥ 1 source pixel): every source pixel it overlaps by
    more than a rounding error. Upsampling: the one source pixel under the target's centre.
    """
    scale = n_src / n_new
    j = np.arange(n_new)
    if scale >= 1.0:
        eps = 1e-9 * scale
        lo = np.floor(j * scale + eps).astype(int)
        hi = np.ceil((j + 1) * scale - eps).astype(int)
    else:
        lo = np.floor((j + 0.5) * scale).astype(int)
        hi = lo + 1
    lo = np.clip(lo, 0, n_src - 1)
    return lo, np.clip(np.maximum(hi, lo + 1), 1, n_src)


def _any_over_ranges(values: np.ndarray, lo: np.ndarray, hi: np.ndarray, axis: int) -> np.ndarray:
    """any(values[..., lo[k]:hi[k], ...]) along ``axis`` for every k, via cumulative sums."""
    counts = np.cumsum(values, axis=axis, dtype=np.int64)
    pad = [(0, 0)] * values.ndim
    pad[axis] = (1, 0)
    counts = np.pad(counts, pad)
    return (np.take(counts, hi, axis=axis) - np.take(counts, lo, axis=axis)) > 0


def resample_square(occupied: np.ndarray, size_m: tuple, resolution: float) -> np.ndarray:
    """Resample an occupancy bitmap stretched to ``size_m`` (W, H m) onto square pixels.

    The result has round(W/res) x round(H/res) pixels. Per axis: when target pixels are
    larger than source pixels (downsampling) a target pixel is occupied if ANY source pixel it
    covers is, so thin walls survive; when they are smaller (upsampling) it copies the source
    pixel under its centre (nearest neighbour), so walls keep their position and thickness.
    """
    rows, cols = occupied.shape
    new_cols = max(1, int(round(size_m[0] / resolution)))
    new_rows = max(1, int(round(size_m[1] / resolution)))
    lo_c, hi_c = _source_ranges(cols, new_cols)
    lo_r, hi_r = _source_ranges(rows, new_rows)
    by_cols = _any_over_ranges(np.asarray(occupied, dtype=bool), lo_c, hi_c, axis=1)
    return _any_over_ranges(by_cols, lo_r, hi_r, axis=0)
