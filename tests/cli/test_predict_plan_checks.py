"""``slam-predict predict`` on plans that are no building, are at the wrong scale, are partly
unreachable or too large to decode; and outputs that fall outside the model's range (issue 19).
"""
from __future__ import annotations

import json
import struct
import zlib

import cv2
import numpy as np
import pytest

from slam_predict.cli.main import main

RES = "0.05"


def two_rooms(door_open: bool = True) -> np.ndarray:
    """A 20 m x 10 m plan at 0.05 m/px: two 10 m x 10 m rooms, a 1 m door between them."""
    image = np.zeros((220, 420), np.uint8)
    image[10:-10, 10:-10] = 255
    image[10:-10, 207:213] = 0
    if door_open:
        image[100:120, 207:213] = 255
    return image


@pytest.fixture(scope="module")
def plans(tmp_path_factory):
    folder = tmp_path_factory.mktemp("plans")
    cv2.imwrite(str(folder / "two_room.png"), two_rooms(True))
    cv2.imwrite(str(folder / "closed_door.png"), two_rooms(False))
    noise = np.random.default_rng(0).random((200, 200)) > 0.5
    cv2.imwrite(str(folder / "noise.png"), noise.astype(np.uint8) * 255)
    return folder


def predict(capsys, *argv):
    code = main(["predict", *map(str, argv)])
    out, err = capsys.readouterr()
    return code, out, err


def refused(capsys, *argv) -> str:
    code, out, err = predict(capsys, *argv)
    assert code == 2 and out == "", out
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    return err.strip()


def test_noise_image_is_refused_in_one_line(plans, capsys):
    """All 43 features of random noise are 0; the old code predicted 0.592 m from them."""
    err = refused(capsys, plans / "noise.png", "--resolution", RES)
    assert "noise.png" in err and "no Voronoi graph and no rooms" in err


def test_two_room_plan_is_below_the_model_range_not_0(plans, capsys):
    """The old code printed 0.000 m (90 % interval 0.000–0.171 m) after clipping -0.78 m."""
    code, out, err = predict(capsys, plans / "two_room.png", "--resolution", RES, "--json")
    assert code == 0, err
    result = json.loads(out)
    entry = result["trans_mean"]
    assert entry["status"] == "below_range" and entry["value"] is None
    assert entry["raw_value"] < 0
    assert any("below the model's range" in w and f"{entry['raw_value']:.4g}" in w
               for w in result["warnings"])
    for comp in ("trans_mean", "trans_std", "rot_mean", "rot_std"):
        e = result[comp]
        if e["status"] == "ok":
            assert 0 <= e["low"] <= e["value"] <= e["high"] and e["low"] < e["high"]
    code, out, _ = predict(capsys, plans / "two_room.png", "--resolution", RES)
    assert code == 0
    line = next(x for x in out.splitlines() if x.strip().startswith("trans_mean"))
    assert "below the model's range (raw output -" in line and "0.000 m" not in line


def test_closed_door_warns_with_the_share_used(plans, capsys):
    """Half the free space is behind a closed door: the old output said nothing."""
    code, out, err = predict(capsys, plans / "closed_door.png", "--resolution", RES, "--json",
                             "--component", "trans_std")
    assert code == 0, err
    result = json.loads(out)
    assert result["free_space"]["reachable_share"] == pytest.approx(0.5, abs=0.01)
    assert any(w.startswith("only 50 % of the free space (99 of 197 m²) is reachable")
               for w in result["warnings"])
    code, out, _ = predict(capsys, plans / "closed_door.png", "--resolution", RES,
                           "--component", "trans_std")
    assert code == 0 and "warning: only 50 % of the free space" in out
    code, out, _ = predict(capsys, plans / "two_room.png", "--resolution", RES, "--json",
                           "--component", "trans_std")
    assert json.loads(out)["free_space"]["reachable_share"] == 1.0
    assert not any("reachable" in w for w in json.loads(out)["warnings"])


def test_absurd_resolution_is_refused_unless_forced(plans, capsys):
    """5 m/px makes the 20 m plan a 2 km building: the old code predicted 158 m."""
    err = refused(capsys, plans / "two_room.png", "--resolution", "5.0")
    assert "free area 1.97e+06 m² is larger than any building" in err
    assert "--resolution" in err and "--force" in err
    code, out, err = predict(capsys, plans / "two_room.png", "--resolution", "5.0", "--force",
                             "--component", "trans_mean")
    assert code == 0, err
    err = refused(capsys, plans / "two_room.png", "--resolution", "0.001")
    assert "smaller than any building" in err


def huge_png_header(path, width: int = 20000, height: int = 20000) -> None:
    """A 20 x 20 px PNG whose IHDR claims ``width`` x ``height`` (CRC fixed): decoding it
    would fail, reading its header does not."""
    image = np.full((20, 20), 255, np.uint8)
    ok, buf = cv2.imencode(".png", image)
    data = bytearray(buf.tobytes())
    assert ok and data[12:16] == b"IHDR"
    data[16:24] = struct.pack(">II", width, height)
    data[29:33] = struct.pack(">I", zlib.crc32(bytes(data[12:29])))
    path.write_bytes(bytes(data))


def test_oversize_image_is_refused_from_its_header(tmp_path, capsys, monkeypatch):
    huge_png_header(tmp_path / "huge.png")

    def no_decoding(*args, **kwargs):
        raise AssertionError("the image was decoded")

    monkeypatch.setattr(cv2, "imread", no_decoding)
    err = refused(capsys, tmp_path / "huge.png", "--resolution", RES)
    assert "20000 x 20000 px (400 M px" in err and "--max-pixels 400000000" in err
    err = refused(capsys, tmp_path / "huge.png", "--resolution", RES, "--max-pixels", "0")
    assert "--max-pixels must be ≥ 1" in err
