"""Plan plausibility (free area, extent), reachability from the start and the image size guard,
each against a count done by hand on small bitmaps."""
from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from slam_predict.errors import InputError
from slam_predict.world import bitmap
from slam_predict.world.model import World
from slam_predict.world.plausibility import (
    check_scale,
    free_area_m2,
    free_extent_m,
    reachability,
    unreachable_warning,
)
from slam_predict.world.start import resolve_start


def rooms(side: int, res: float, door: bool, start_col: int = 5) -> World:
    """Two side x side px rooms in a wall frame, one wall column between them."""
    occupied = np.ones((side + 2, 2 * side + 3), bool)
    occupied[1:-1, 1:side + 1] = False
    occupied[1:-1, side + 2:-1] = False
    if door:
        occupied[side // 2, side + 1] = False
    world = World(name="r", occupied=occupied, resolution=res, origin=(0.0, 0.0),
                  provenance={"format": "image", "source": "r.png"})
    x, y = world.cell_to_world((side // 2, start_col))
    return resolve_start(world, [x, y])


def test_area_and_extent_by_count():
    world = rooms(20, 0.5, door=False)
    assert free_area_m2(world) == pytest.approx(2 * 400 * 0.25)
    assert free_extent_m(world) == pytest.approx(((2 * 20 + 1) * 0.5, 20 * 0.5))


@pytest.mark.parametrize("res, problem", [(0.05, "smaller than any building"),
                                          (0.5, None),
                                          (12.0, "larger than any building")])
def test_scale_limits(res, problem):
    world = rooms(20, res, door=True)  # 801 free px: 2.0 m², 200 m², 115,344 m²
    if problem is None:
        check_scale(world)
        return
    with pytest.raises(InputError, match=problem) as info:
        check_scale(world)
    assert "--resolution" in str(info.value) and "--force" in str(info.value)
    check_scale(world, force=True)


def test_extent_beyond_any_building():
    """A 1-px-wide corridor 2.5 km long has a plausible area (2,500 m²) but no building's
    extent."""
    occupied = np.ones((3, 2502), bool)
    occupied[1, 1:-1] = False
    world = World(name="c", occupied=occupied, resolution=1.0, origin=(0.0, 0.0))
    with pytest.raises(InputError, match="spans 2500 x 1 m"):
        check_scale(world)


def test_reachable_share_of_a_closed_door():
    closed = rooms(20, 0.5, door=False)
    reach = reachability(closed)
    assert reach.reachable_m2 == pytest.approx(100.0) and reach.free_m2 == pytest.approx(200.0)
    assert reach.share == pytest.approx(0.5) and reach.largest_cut_m2 == pytest.approx(100.0)
    assert unreachable_warning(closed).startswith("only 50 % of the free space (100 of 200 m²)")
    opened = rooms(20, 0.5, door=True)
    assert reachability(opened).share == 1.0 and unreachable_warning(opened) is None


def test_small_enclosed_specks_do_not_warn():
    """Scanned maps hold specks of enclosed free space that are no rooms (< 4 m²)."""
    world = rooms(20, 0.5, door=True)
    occupied = world.occupied.copy()
    occupied[3:6, 3:6] = True
    occupied[4, 4] = False  # a 0.25 m² speck inside a pillar
    speck = world.replace(occupied=occupied)
    assert reachability(speck).largest_cut_m2 == pytest.approx(0.25)
    assert unreachable_warning(speck) is None


def test_header_size_without_decoding(tmp_path):
    path = tmp_path / "big.png"
    Image.new("1", (3000, 2000), 1).save(path)
    assert bitmap.header_size(str(path)) == (3000, 2000)
    assert bitmap.header_size(__file__) is None  # not an image: the decoder decides
    with bitmap.pixel_limit(5_999_999):
        with pytest.raises(InputError, match=r"3000 x 2000 px \(6 M px"):
            bitmap.read_grey(path)
    with bitmap.pixel_limit(6_000_000):
        assert bitmap.read_grey(path).shape == (2000, 3000)
    assert bitmap.read_grey(path).shape == (2000, 3000)  # the default limit is restored


def test_pillow_bomb_warning_and_error_do_not_leak(tmp_path, recwarn, monkeypatch):
    """Above MAX_IMAGE_PIXELS Pillow warns (DecompressionBombWarning), above twice that it
    raises: neither may reach the user (one-line errors) nor stop the header read. Pillow's
    limit (89 M px) is lowered to 1,000 px to keep the images small."""
    monkeypatch.setattr(Image, "MAX_IMAGE_PIXELS", 1000)
    for side in (40, 100):  # 1,600 px: warning; 10,000 px: error
        Image.new("1", (side, side), 1).save(tmp_path / "h.png")
        assert bitmap.header_size(str(tmp_path / "h.png")) == (side, side)
    assert not [w for w in recwarn if "DecompressionBomb" in type(w.message).__name__]
    assert Image.MAX_IMAGE_PIXELS == 1000
