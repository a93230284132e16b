"""Layout XML: parsing, door rule, rasterisation, errors; every shipped-data layout."""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from slam_predict.cli.main import main
from slam_predict.errors import InputError
from slam_predict.world import raster
from slam_predict.world.layout import load_layout, parse_layout, rasterise_layout

SCALE = """<scale><represented_distance><value>10</value><um>pixel</um></represented_distance>
<real_distance><value>90</value><um>cm</um></real_distance></scale>"""  # 1 unit = 0.09 m


def space_xml(sid, label, polygon, portals=()):
    """One <space>: outline walls split at each portal point; portals = [(point, other id)]."""
    pts = "".join(f'<point x="{x}" y="{y}" />' for x, y in list(polygon) + [polygon[0]])
    segs, refs = [], []
    for i, (a, b) in enumerate(zip(polygon, list(polygon[1:]) + [polygon[0]], strict=False)):
        segs.append(f'<linesegment id="{sid}w{i}"><point x="{a[0]}" y="{a[1]}" />'
                    f'<point x="{b[0]}" y="{b[1]}" /><class>WALL</class></linesegment>')
    for k, ((x, y), other) in enumerate(portals):
        segs.append(f'<linesegment id="{sid}p{k}"><point x="{x}" y="{y}" /><point x="{x}" '
                    f'y="{y}" /><class>PORTAL</class></linesegment>')
        refs.append(f'<portal><linesegment>{sid}p{k}</linesegment><target><id>{sid}</id>'
                    f'<id>{other}</id></target></portal>')
    return (f'<space id="{sid}"><labels><type>R</type><label>{label}</label></labels>'
            f'<bounding_polygon>{pts}</bounding_polygon><space_representation>{"".join(segs)}'
            f'</space_representation><portals>{"".join(refs)}</portals></space>')


def building_xml(spaces, scale=SCALE):
    return (f'<building id="b"><name>x</name>{scale}<building_type><main_type>OFFICE'
            f'</main_type></building_type><floor><spaces>{"".join(spaces)}</spaces></floor>'
            f'</building>')


@pytest.fixture
def two_rooms(tmp_path):
    """Room A (0..100 x 0..50 units) and corridor B (0..100 x 50..80) with a portal at (60, 50)."""
    a = space_xml("A", "OFFICE", [(0, 0), (100, 0), (100, 50), (0, 50)], [((60, 50), "B")])
    b = space_xml("B", "CORRIDOR", [(0, 50), (100, 50), (100, 80), (0, 80)], [((60, 50), "A")])
    path = tmp_path / "two.xml"
    path.write_text(building_xml([a, b]))
    return path


def test_parse_scale_spaces_portals(two_rooms):
    layout = parse_layout(two_rooms)
    assert layout.unit_m == pytest.approx(0.09)
    assert [s.id for s in layout.spaces] == ["A", "B"]
    assert layout.extent == (0, 0, 100, 80)
    assert layout.spaces[0].walls.shape == (4, 2, 2)
    point, other = layout.spaces[0].portals[0]
    assert other == "B" and np.allclose(point, [60, 50])


def test_two_rooms_world_frame_rooms_and_door(two_rooms):
    world = load_layout(two_rooms, resolution=0.05)
    assert world.origin == (0.0, 0.0)
    # the drawing centre (50, 40) is the world origin; y flips: A (y 0..50) is on top
    room_a = world.rooms[0].polygon
    assert np.allclose(room_a.min(axis=0), [-4.5, -0.9]) and np.allclose(room_a.max(axis=0),
                                                                        [4.5, 3.6])
    assert len(world.doors) == 1
    door = world.doors[0]
    assert set(door.rooms) == {"A", "B"}
    assert np.allclose(door.segment.mean(axis=0), [0.9, -0.9])  # (60, 50) units
    assert np.hypot(*(door.segment[1] - door.segment[0])) == pytest.approx(0.9)
    assert abs(door.segment[1, 1] - door.segment[0, 1]) < 1e-9  # along the horizontal wall
    _, count = raster.label_free(~world.occupied)
    assert count == 1
    # the door is open at its centre, the wall is closed 1 m beside it
    assert world.is_free_at([0.9, -0.9]) and not world.is_free_at([-0.5, -0.9])
    assert world.is_free_at(world.start_pose[:2])


def test_closing_the_ground_truth_door_splits_the_rooms(two_rooms):
    world = rasterise_layout(two_rooms, resolution=0.05)
    free = ~world.occupied
    grid = raster.Grid(*world.shape, world.resolution, world.origin)
    raster.draw_segments(free, grid, [d.segment for d in world.doors], 0.3, False)
    assert raster.label_free(free)[1] == 2


def test_area_formula_on_two_rooms(two_rooms):
    wall = 0.15
    world = rasterise_layout(two_rooms, resolution=0.02, wall_thickness=wall)
    expected = sum(raster.polygon_area(r.polygon) - 0.5 * wall * raster.polygon_perimeter(
        r.polygon) for r in world.rooms)
    assert world.free_area_m2 == pytest.approx(expected, rel=0.02)


def test_room_without_portal_gets_an_inferred_door(tmp_path):
    a = space_xml("A", "OFFICE", [(0, 0), (100, 0), (100, 50), (0, 50)])
    b = space_xml("B", "CORRIDOR", [(0, 50), (100, 50), (100, 80), (0, 80)])
    path = tmp_path / "noportal.xml"
    path.write_text(building_xml([a, b]))
    world = rasterise_layout(path)
    assert world.provenance["inferred_doors"] == [["A", "B"]]
    assert len(world.doors) == 1 and raster.label_free(~world.occupied)[1] == 1


def test_wider_door_option(two_rooms):
    world = rasterise_layout(two_rooms, door_width=1.2)
    assert np.hypot(*(world.doors[0].segment[1] - world.doors[0].segment[0])) == pytest.approx(1.2)
    assert world.is_free_at([0.9 + 0.5, -0.9]) and not world.is_free_at([0.9 + 0.7, -0.9])


@pytest.mark.parametrize("text, problem", [
    (building_xml([space_xml("A", "X", [(0, 0), (9, 0), (9, 9)])], scale=""), "no <scale>"),
    (building_xml([]), "no spaces"),
    ("<building><scale>", "malformed XML"),
    (building_xml([space_xml("A", "X", [(0, 0), (9, 0), (9, 9)])],
                  scale=SCALE.replace(">10<", ">0<")), "must be > 0"),
    (building_xml([space_xml("A", "X", [(0, 0), ("a", 0), (9, 9)])]), "bad point"),
])
def test_bad_layouts_raise_input_error(tmp_path, text, problem):
    path = tmp_path / "bad.xml"
    path.write_text(text)
    with pytest.raises(InputError) as info:
        parse_layout(path)
    assert problem in str(info.value) and str(path) in str(info.value)


@pytest.mark.parametrize("text, problem", [
    (building_xml([space_xml("A", "X", [(0, 0), (9, 0), (9, 9)])], scale=""), "no <scale>"),
    (building_xml([]), "no spaces"),
    ("<building", "malformed XML"),
])
def test_bad_layout_cli_one_line_exit_2(tmp_path, capsys, text, problem):
    path = tmp_path / "bad.xml"
    path.write_text(text)
    assert main(["worlds", "validate", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and problem in err and str(path) in err


def test_missing_layout_file(tmp_path):
    with pytest.raises(InputError, match="not found"):
        load_layout(tmp_path / "nope.xml")


def layout_files():
    """The layout XMLs of ../shared/data (same location rule as the shared_data fixture)."""
    root = Path(__file__).resolve().parents[2]
    folder = Path(os.environ.get("SLAM_PREDICT_SHARED", root.parent / "shared")) / "data"
    folder = folder / "floorplans" / "layouts"
    return sorted(folder.glob("*.xml")) if folder.is_dir() else []


@pytest.mark.parametrize("path", layout_files() or [None], ids=lambda p: p.stem if p else "absent")
def test_every_data_layout_is_one_building_with_the_expected_area(shared_data, path):
    """Acceptance: ONE connected free space; free area within 5 % of
    Σ area − ½·wall·Σ perimeter; every space with a portal is reachable."""
    if path is None:
        pytest.skip("no layout XML in shared data")
    wall = 0.15
    world = rasterise_layout(path, resolution=0.05, wall_thickness=wall)
    labels, count = raster.label_free(~world.occupied)
    assert count == 1
    expected = sum(raster.polygon_area(r.polygon) - 0.5 * wall * raster.polygon_perimeter(
        r.polygon) for r in world.rooms)
    assert abs(world.free_area_m2 - expected) <= 0.05 * expected
    with_portals = {s.id for s in parse_layout(path).spaces if s.portals}
    assert not with_portals & set(world.provenance["rooms_closed"])
    assert len(world.doors) >= len(world.rooms) - 1


def test_load_plan_passes_layout_options(two_rooms):
    from slam_predict.world.load import load_plan

    world = load_plan(two_rooms, resolution=0.04, wall_thickness=0.2, door_width=1.1,
                      start=[0.0, 1.0, 90.0])
    assert world.resolution == 0.04 and world.provenance["wall_thickness"] == 0.2
    assert np.hypot(*(world.doors[0].segment[1] - world.doors[0].segment[0])) == pytest.approx(
        1.1)
    assert np.allclose(world.start_pose, [0.0, 1.0, np.pi / 2])


def test_start_in_a_wall_is_refused_or_snapped(two_rooms):
    with pytest.raises(InputError, match="inside a wall"):
        load_layout(two_rooms, start=[-4.5, 0.0])
    world = load_layout(two_rooms, start=[-4.5, 0.0], snap_start=True)
    assert world.is_free_at(world.start_pose[:2])
