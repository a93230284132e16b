"""Bitmap loading (1/8/16-bit, grey/colour/alpha/palette) and square resampling."""
from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from slam_predict.errors import InputError
from slam_predict.world.bitmap import load_occupancy, read_grey, resample_square


def room(rows: int = 24, cols: int = 32) -> np.ndarray:
    """Expected occupancy: a walled room with a wall stub; True = obstacle."""
    occ = np.ones((rows, cols), bool)
    occ[2:-2, 2:-2] = False
    occ[8:16, 14:16] = True
    return occ


def as_image(occ: np.ndarray, mode: str) -> Image.Image:
    free8 = np.where(occ, 0, 255).astype(np.uint8)
    if mode == "1":
        return Image.fromarray(free8).convert("1")
    if mode == "L":
        return Image.fromarray(free8)
    if mode == "I;16":
        return Image.fromarray(np.where(occ, 0, 65535).astype(np.uint16))
    if mode == "RGB":   # coloured walls (dark red) on white
        rgb = np.stack([free8, free8, free8], -1)
        rgb[occ] = (120, 0, 0)
        return Image.fromarray(rgb)
    if mode == "RGBA":  # opaque except a transparent outer ring (transparent = obstacle)
        rgba = np.dstack([free8, free8, free8, np.full(occ.shape, 255, np.uint8)])
        rgba[0, :, 3] = 0
        return Image.fromarray(rgba)
    if mode == "LA":
        return Image.fromarray(np.dstack([free8, np.full(occ.shape, 255, np.uint8)]), "LA")
    if mode == "P":
        return Image.fromarray(free8).convert("P")
    raise ValueError(mode)


@pytest.mark.parametrize("mode", ["1", "L", "I;16", "RGB", "RGBA", "LA", "P"])
def test_png_modes_load_to_the_same_occupancy(tmp_path, mode):
    occ = room()
    path = tmp_path / f"plan_{mode.replace(';', '')}.png"
    as_image(occ, mode).save(path)
    assert np.array_equal(load_occupancy(path), occ)


def test_16bit_pgm_and_8bit_pgm(tmp_path):
    import cv2

    occ = room()
    cv2.imwrite(str(tmp_path / "a.pgm"), np.where(occ, 0, 65535).astype(np.uint16))
    cv2.imwrite(str(tmp_path / "b.pgm"), np.where(occ, 0, 254).astype(np.uint8))
    assert read_grey(tmp_path / "a.pgm").dtype == np.uint8
    assert np.array_equal(load_occupancy(tmp_path / "a.pgm"), occ)
    assert np.array_equal(load_occupancy(tmp_path / "b.pgm", free_threshold=250), occ)


def test_threshold_rule_on_grey_levels(tmp_path):
    grey = np.full((10, 10), 0, np.uint8)
    grey[2:8, 2:8] = 255
    grey[4, 2:8] = 249      # just below the threshold: obstacle
    grey[5, 2:8] = 250      # at the threshold: free
    Image.fromarray(grey).save(tmp_path / "g.png")
    occ = load_occupancy(tmp_path / "g.png")
    assert occ[4, 2:8].all() and not occ[5, 2:8].any()
    assert not load_occupancy(tmp_path / "g.png", free_threshold=240)[4, 2:8].any()


def test_unreadable_image(tmp_path):
    (tmp_path / "x.png").write_bytes(b"not an image at all")
    with pytest.raises(InputError, match="cannot read image"):
        read_grey(tmp_path / "x.png")
    with pytest.raises(InputError, match="image not found"):
        read_grey(tmp_path / "missing.png")


def resample_reference(occ: np.ndarray, size, res) -> np.ndarray:
    """Slow reference: per axis, downsampling = any covered source pixel (overlap > 0),
    upsampling = the source pixel under the target's centre."""
    rows, cols = occ.shape
    new_c, new_r = max(1, round(size[0] / res)), max(1, round(size[1] / res))

    def covered(j, n_src, n_new):
        s = n_src / n_new
        if s >= 1:
            a, b = j * s, (j + 1) * s
            return [k for k in range(n_src) if min(b, k + 1) - max(a, k) > 1e-9 * s]
        return [min(int((j + 0.5) * s), n_src - 1)]

    out = np.zeros((new_r, new_c), bool)
    for r in range(new_r):
        rs = covered(r, rows, new_r)
        for c in range(new_c):
            cs = covered(c, cols, new_c)
            out[r, c] = occ[np.ix_(rs, cs)].any()
    return out


@pytest.mark.parametrize("seed", range(20))
def test_resample_square_matches_reference(seed):
    rng = np.random.default_rng(seed)
    rows, cols = rng.integers(3, 40, size=2)
    occ = rng.random((rows, cols)) < 0.2
    size = (float(rng.uniform(0.5, 5)), float(rng.uniform(0.5, 5)))
    res = float(rng.uniform(0.04, 0.4))
    assert np.array_equal(resample_square(occ, size, res), resample_reference(occ, size, res))


def test_downsampling_keeps_one_pixel_walls():
    occ = np.zeros((100, 100), bool)
    occ[:, 37] = True
    occ[61, :] = True
    small = resample_square(occ, (10.0, 10.0), 0.3)   # 0.1 → 0.3 m/px
    assert small.any(axis=0).sum() == small.shape[1] and small.any(axis=1).sum() == small.shape[0]
    assert small[:, 12].all() and small[20, :].all()
