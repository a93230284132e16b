"""map_server PGM + YAML maps."""
from __future__ import annotations

import numpy as np
import pytest
import yaml

from slam_predict.errors import InputError
from slam_predict.formats.mapserver import (
    decode_pgm,
    encode_pgm,
    occupancy_to_image,
    read_map,
    write_map,
    write_occupancy,
)


def test_occupancy_to_image_map_saver_values_and_flip():
    grid = np.array([[0, 100, -1], [25, 65, 50]], dtype=np.int8)   # row 0 = bottom
    image = occupancy_to_image(grid)
    # Row 0 of the image is the top = the last grid row.
    assert image[0].tolist() == [254, 0, 205]
    assert image[1].tolist() == [254, 0, 205]
    assert occupancy_to_image(np.array([[-1, 0, 100, 30]]))[0].tolist() == [205, 254, 0, 205]


def test_write_read_round_trip(tmp_path):
    rng = np.random.default_rng(0)
    grid = rng.choice(np.array([-1, 0, 100], dtype=np.int8), size=(40, 70))
    pgm = write_occupancy(tmp_path / "map.yaml", grid, 0.05, (-1.75, -1.0, 0.0))
    assert pgm.name == "map.pgm" and pgm.read_bytes()[:2] == b"P5"
    meta = yaml.safe_load((tmp_path / "map.yaml").read_text())
    assert meta == {"image": "map.pgm", "resolution": 0.05, "origin": [-1.75, -1.0, 0.0],
                    "negate": 0, "occupied_thresh": 0.65, "free_thresh": 0.196}
    loaded = read_map(tmp_path / "map.yaml")
    assert loaded.image.shape == (40, 70) and loaded.resolution == 0.05
    assert set(np.unique(loaded.image)) <= {0, 205, 254}
    np.testing.assert_array_equal(loaded.to_occupancy(), grid)   # map_server's trinary rule


def test_ascii_pgm_and_comments():
    data = b"P2\n# c\n3 2\n# d\n15\n0 15 7\n15 15 0\n"
    image = decode_pgm(data)
    assert image.tolist() == [[0, 255, 119], [255, 255, 0]]
    assert decode_pgm(encode_pgm(image, "x")).tolist() == image.tolist()


def test_png_image_via_opencv(tmp_path):
    import cv2

    image = np.full((5, 6), 254, np.uint8)
    image[2, 3] = 0
    cv2.imwrite(str(tmp_path / "m.png"), image)
    (tmp_path / "m.yaml").write_text("image: m.png\nresolution: 0.1\norigin: [0, 0, 0]\n")
    loaded = read_map(tmp_path / "m.yaml")
    np.testing.assert_array_equal(loaded.image, image)
    assert loaded.to_occupancy()[2, 3] == 100   # row 2 from the top of 5 = row 2 from the bottom


@pytest.mark.parametrize("yaml_text, words", [
    ("resolution: 0.1\norigin: [0, 0, 0]\n", "lacks 'image'"),
    ("image: none.pgm\nresolution: 0.1\norigin: [0, 0, 0]\n", "not found"),
    ("image: m.pgm\nresolution: 0.1\norigin: [0, 0]\n", "origin"),
    ("[1, 2", "cannot read map YAML"),
])
def test_bad_yaml(tmp_path, yaml_text, words):
    (tmp_path / "m.pgm").write_bytes(encode_pgm(np.zeros((2, 2), np.uint8)))
    (tmp_path / "m.yaml").write_text(yaml_text)
    with pytest.raises(InputError, match=words):
        read_map(tmp_path / "m.yaml")


def test_truncated_pgm(tmp_path):
    with pytest.raises(InputError, match="pixels"):
        decode_pgm(b"P5\n4 4\n255\n" + bytes(10))


def test_write_map_image_as_given(tmp_path):
    image = np.array([[0, 205], [254, 254]], np.uint8)
    write_map(tmp_path / "m.yaml", image, 0.025, (1.0, 2.0, 0.0), occupied_thresh=0.7)
    loaded = read_map(tmp_path / "m.yaml")
    np.testing.assert_array_equal(loaded.image, image)
    assert loaded.occupied_thresh == 0.7 and loaded.origin == (1.0, 2.0, 0.0)
