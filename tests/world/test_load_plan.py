"""load_plan: format dispatch, map_server YAML frames, start handling, errors, the ipa maps."""
from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import cv2
import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.world.load import load_plan
from slam_predict.world.stagefile import write_world

IPA_MAPS = ["Freiburg79_scan", "NLB", "lab_a_scan", "lab_b_scan", "lab_c_scan", "lab_intel",
            "lab_ipa", "office_a", "office_b", "office_c", "office_d", "office_e", "office_h"]


def plan_png(path: Path, rows: int = 30, cols: int = 40) -> Path:
    """A walled room with a pillar; free = 255."""
    grey = np.zeros((rows, cols), np.uint8)
    grey[2:-2, 2:-2] = 255
    grey[12:16, 18:22] = 0
    cv2.imwrite(str(path), grey)
    return path


def write_yaml(path: Path, image: str, resolution=0.05, origin=(-1.0, -2.0, 0.0), **extra):
    lines = [f"image: {image}", f"resolution: {resolution}", f"origin: {list(origin)}",
             "negate: 0", "occupied_thresh: 0.65", "free_thresh: 0.196"]
    lines += [f"{k}: {v}" for k, v in extra.items()]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_png_with_resolution(tmp_path):
    world = load_plan(plan_png(tmp_path / "p.png"), resolution=0.1)
    assert world.shape == (30, 40) and world.resolution == 0.1 and world.origin == (0.0, 0.0)
    assert world.free_area_m2 == pytest.approx((26 * 36 - 16) * 0.01)
    assert world.provenance["format"] == "image" and world.provenance["start_given"] is False
    # default start: the free cell of largest clearance
    assert world.is_free_at(world.start_pose[:2])


def test_png_takes_resolution_and_origin_from_yaml_beside(tmp_path):
    png = plan_png(tmp_path / "p.png")
    write_yaml(tmp_path / "p.yaml", "p.png", resolution=0.05, origin=(-1.0, -2.0, 0.0))
    world = load_plan(png)
    assert world.resolution == 0.05
    # origin = map-frame pose of the lower-left corner; World.origin = bitmap centre
    assert world.origin == pytest.approx((-1.0 + 40 * 0.05 / 2, -2.0 + 30 * 0.05 / 2))
    assert load_plan(png, resolution=0.2).resolution == 0.2   # the argument wins


def test_map_server_yaml_as_plan_uses_its_thresholds(tmp_path):
    grey = np.full((30, 40), 205, np.uint8)       # unknown outside, as map_saver writes
    grey[3:-3, 3:-3] = 254
    grey[3:-3, 3] = 0
    grey[10, 10] = 220                            # p = 0.137 < 0.196 → free for map_server
    cv2.imwrite(str(tmp_path / "m.pgm"), grey)
    yaml = write_yaml(tmp_path / "m.yaml", "m.pgm", resolution=0.1, origin=(2.0, 3.0, 0.0))
    world = load_plan(yaml)
    assert world.provenance["format"] == "map_server"
    expected_free = (255.0 - grey) / 255.0 < 0.196
    expected_free[:, :4] = False
    expected_free[grey == 205] = False
    assert np.array_equal(~world.occupied, expected_free)
    assert world.origin == pytest.approx((2.0 + 2.0, 3.0 + 1.5))
    # a pose given in the map frame lands where map_server would put it
    x, y = 2.0 + 10.5 * 0.1, 3.0 + (30 - 10.5) * 0.1    # centre of image pixel (10, 10)
    assert world.world_to_cell(np.array([x, y])).tolist() == [10, 10]


def test_negated_yaml(tmp_path):
    grey = np.full((20, 20), 255, np.uint8)
    grey[2:-2, 2:-2] = 0                           # negate: black = free
    cv2.imwrite(str(tmp_path / "n.png"), grey)
    yaml = write_yaml(tmp_path / "n.yaml", "n.png")
    yaml.write_text(yaml.read_text().replace("negate: 0", "negate: 1"))
    assert load_plan(yaml).free_area_m2 == pytest.approx(16 * 16 * 0.0025)


def test_world_file_dispatch_keeps_its_start(tmp_path):
    world = load_plan(plan_png(tmp_path / "p.png"), resolution=0.1, start=(-1.0, 0.5, 90))
    path = write_world(world, tmp_path / "w" / "p.world")
    back = load_plan(path)
    assert back.start_pose == pytest.approx([-1.0, 0.5, math.pi / 2])
    moved = load_plan(path, start=(1.0, -0.5))
    assert moved.start_pose == pytest.approx([1.0, -0.5, 0.0])


def test_snap_start_moves_a_pose_out_of_the_pillar(tmp_path):
    png = plan_png(tmp_path / "p.png")
    with pytest.raises(InputError, match="inside a wall"):
        load_plan(png, resolution=0.1, start=(0.0, 0.0))
    world = load_plan(png, resolution=0.1, start=(0.0, 0.0), snap_start=True)
    assert world.is_free_at(world.start_pose[:2])
    assert np.hypot(*world.start_pose[:2]) < 0.6


@pytest.mark.parametrize("resolution", [0.05, 0.1])
def test_a_snapped_start_leaves_the_footprint_free_at_every_yaw(tmp_path, resolution):
    from slam_predict.sim.raycast import LaserGrid
    world = load_plan(plan_png(tmp_path / "p.png"), resolution=resolution, start=(0.0, 0.0),
                      snap_start=True)
    grid = LaserGrid.of_world(world)
    x, y = world.start_pose[:2]
    side = world.robot.footprint_side
    assert not any(grid.collides(x, y, yaw, side) for yaw in np.linspace(0, np.pi, 13))


@pytest.mark.parametrize("kwargs, fragment", [
    ({"resolution": 0}, "--resolution must be > 0"),
    ({"resolution": -0.05}, "--resolution must be > 0"),
    ({}, "give --resolution"),
    ({"resolution": 0.1, "start": (100.0, 0.0)}, "outside the map"),
    ({"resolution": 0.1, "start": (0.0, 0.0)}, "inside a wall"),
    ({"resolution": 0.1, "start": (0.0,)}, "--start takes X Y [YAW]"),
    ({"resolution": 0.1, "free_threshold": 0}, "free threshold"),
])
def test_image_errors(tmp_path, kwargs, fragment):
    with pytest.raises(InputError) as err:
        load_plan(plan_png(tmp_path / "p.png"), **kwargs)
    assert fragment in err.value.problem


def test_bad_files(tmp_path):
    with pytest.raises(InputError, match="plan not found"):
        load_plan(tmp_path / "nope.png", resolution=0.1)
    (tmp_path / "bad.png").write_bytes(b"\x89PNG\r\n\x1a\n garbage")
    with pytest.raises(InputError, match="cannot read image"):
        load_plan(tmp_path / "bad.png", resolution=0.1)
    cv2.imwrite(str(tmp_path / "black.png"), np.zeros((10, 10), np.uint8))
    with pytest.raises(InputError, match="no free space"):
        load_plan(tmp_path / "black.png", resolution=0.1)
    cv2.imwrite(str(tmp_path / "open.png"), np.full((10, 10), 255, np.uint8))
    with pytest.raises(InputError, match="no enclosed building"):
        load_plan(tmp_path / "open.png", resolution=0.1)
    (tmp_path / "plan.dxf").write_text("0\nSECTION\n")
    with pytest.raises(InputError, match="unknown plan format '.dxf'"):
        load_plan(tmp_path / "plan.dxf")
    plan_png(tmp_path / "p.png")
    world = write_world(load_plan(tmp_path / "p.png", resolution=0.1), tmp_path / "p.world")
    with pytest.raises(InputError, match="does not apply to a .world"):
        load_plan(world, resolution=0.1)
    (tmp_path / "y.yaml").write_text("image: nothing.png\nresolution: 0.05\norigin: [0, 0, 0]\n")
    with pytest.raises(InputError, match="not found"):
        load_plan(tmp_path / "y.yaml")
    write_yaml(tmp_path / "z.yaml", "p.png", resolution=-1)
    with pytest.raises(InputError, match="resolution must be > 0"):
        load_plan(tmp_path / "z.yaml")


@pytest.mark.skipif(importlib.util.find_spec("slam_predict.world.layout") is None,
                    reason="layout XML reader (slam_predict.world.layout) not installed yet")
def test_layout_xml_dispatch(shared_data):
    xml = sorted((shared_data / "floorplans" / "layouts").glob("*.xml"))[0]
    world = load_plan(xml, resolution=0.1)
    assert world.resolution == 0.1 and world.provenance["format"] == "layout-xml"
    assert world.is_free_at(world.start_pose[:2])


@pytest.mark.parametrize("name", IPA_MAPS)
def test_every_ipa_map_loads_at_5cm(shared_data, name):
    path = shared_data / "floorplans" / "ipa" / f"{name}.png"
    world = load_plan(path, resolution=0.05)
    grey = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    assert world.shape == grey.shape[:2] and world.resolution == 0.05
    assert 100.0 < world.free_area_m2 < 0.05 ** 2 * grey.shape[0] * grey.shape[1]
    assert world.is_free_at(world.start_pose[:2])
    # nothing free may touch the border (outside removed)
    occ = world.occupied
    assert occ[0].all() and occ[-1].all() and occ[:, 0].all() and occ[:, -1].all()
