"""Bitmap floor plans (PNG/PGM, 1/8/16-bit, grey or colour) → occupancy.

The threshold rule (one rule for every image):
1. Convert to 8-bit grey: 16-bit values are divided by 257; colour uses ITU-R 601 luma;
   an alpha channel is composited onto black (transparent = obstacle).
2. A pixel is free iff its grey value ≥ ``free_threshold`` (default 250, the rule of the ipa
   room-segmentation maps; anti-aliased wall edges and grey "outside" fills count as obstacle).
3. Free space 4-connected to the image border is outside the building: it becomes obstacle
   (with a warning). An image with nothing left is not an enclosed building.
"""
from __future__ import annotations

import logging
import os
from typing import Optional

import cv2
import numpy as np
from scipy import ndimage

from slam_predict.errors import InputError, require_file

LOG = logging.getLogger(__name__)
FREE_THRESHOLD = 250


def read_grey(path: os.PathLike | str) -> np.ndarray:
    """Read an image as 8-bit grey (rows, cols); InputError when unreadable or corrupt."""
    path = require_file(path, "image")
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


def remove_outside(free: np.ndarray, source: Optional[str] = None) -> np.ndarray:
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


def resample_square(occupied: np.ndarray, size_m: tuple, resolution: float) -> np.ndarray:
    """Resample an occupancy bitmap stretched to ``size_m`` (W, H m) onto square pixels.

    Nearest-neighbour sampling at pixel centres, so walls keep their position; the result has
    round(W/res) x round(H/res) pixels.
    """
    rows, cols = occupied.shape
    new_cols = max(1, int(round(size_m[0] / resolution)))
    new_rows = max(1, int(round(size_m[1] / resolution)))
    src_c = np.minimum(((np.arange(new_cols) + 0.5) * cols / new_cols).astype(int), cols - 1)
    src_r = np.minimum(((np.arange(new_rows) + 0.5) * rows / new_rows).astype(int), rows - 1)
    return occupied[np.ix_(src_r, src_c)]
