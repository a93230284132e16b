"""Procedural generator: connectivity, area, ground-truth rooms/doors, determinism, CLI."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from slam_predict.cli.main import main
from slam_predict.errors import InputError
from slam_predict.world import raster
from slam_predict.world.generator import generate, metadata
from slam_predict.world.generator.params import STYLES, sample_params
from slam_predict.world.generator.spine import make_spine

CLOSE_THICKNESS = 0.4  # m: ≥ the deepest door cut (outer wall 0.3 + 2 cells)


def regions_with_doors_closed(world):
    """(labels, count) of free space once every ground-truth door is drawn shut."""
    free = ~world.occupied
    grid = raster.Grid(*world.shape, world.resolution, world.origin)
    raster.draw_segments(free, grid, [d.segment for d in world.doors], CLOSE_THICKNESS, False)
    return raster.label_free(free), free


def room_owner(world):
    grid = raster.Grid(*world.shape, world.resolution, world.origin)
    owner = np.zeros(world.shape, dtype=np.int32)
    for k, room in enumerate(world.rooms):
        raster.fill_polygons(owner, grid, [room.polygon], k + 1)
    return owner


def check_world(world, area):
    """The acceptance checks of the issue for one generated world."""
    labels, count = raster.label_free(~world.occupied)
    assert count == 1, "free space must be one connected component"
    assert world.is_free_at(world.start_pose[:2])
    assert abs(world.free_area_m2 - area) <= 0.15 * area
    (closed_labels, regions), closed = regions_with_doors_closed(world)
    assert regions == len(world.rooms)
    # and the regions are the rooms: each region lies in exactly one room and vice versa
    owner = room_owner(world)
    pairs = np.unique(np.stack([closed_labels[closed], owner[closed]]), axis=1)
    pairs = pairs[:, pairs[1] > 0]
    assert len(np.unique(pairs[0])) == len(pairs[0]) == len(world.rooms)


@pytest.mark.parametrize("kind", ["office", "school"])
@pytest.mark.parametrize("seed", range(50))
def test_generated_building_acceptance(kind, seed):
    check_world(generate(kind, 300.0, seed), 300.0)


@pytest.mark.parametrize("kind, area, seed", [("office", 1500.0, 3), ("school", 2500.0, 4),
                                              ("office", 100.0, 9)])
def test_medium_buildings(kind, area, seed):
    check_world(generate(kind, area, seed), area)


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["office", "school"])
@pytest.mark.parametrize("area", [150.0, 800.0, 3000.0, 6000.0, 10000.0])
@pytest.mark.parametrize("seed", range(6))
def test_generator_sweep(kind, area, seed):
    check_world(generate(kind, area, seed), area)


def test_deterministic_from_seed():
    a, b = generate("office", 400.0, 7), generate("office", 400.0, 7)
    assert np.array_equal(a.occupied, b.occupied)
    assert np.allclose(a.start_pose, b.start_pose)
    assert [r.id for r in a.rooms] == [r.id for r in b.rooms]
    assert all(np.allclose(r.polygon, s.polygon) for r, s in zip(a.rooms, b.rooms, strict=False))
    c = generate("office", 400.0, 8)
    assert c.occupied.shape != a.occupied.shape or not np.array_equal(c.occupied, a.occupied)


def test_doors_walls_and_metadata_ranges():
    world = generate("school", 1200.0, 2)
    info = world.provenance["generator"]
    params = info["params"]
    assert 0.1 <= params["wall_inner"] <= 0.3 and 0.1 <= params["wall_outer"] <= 0.3
    record = json.loads(json.dumps(metadata(world)))
    assert record["kind"] == "school" and record["seed"] == 2
    assert record["area_requested_m2"] == 1200.0
    assert record["area_m2"] == pytest.approx(world.free_area_m2, abs=0.01)
    assert len(record["rooms"]) == len(world.rooms) and len(record["doors"]) == len(world.doors)
    for door in record["doors"]:
        if door["kind"] == "door":
            assert 0.8 - 1e-6 <= door["width"] <= 1.5 + 1e-6
    labels = {r["category"] for r in record["rooms"]}
    assert "corridor" in labels and "room" in labels
    assert record["start_pose"][2] in (0.0, 90.0)


def test_every_spine_shape_occurs():
    """Across seeds and areas the generator uses every spine shape, courtyards included."""
    seen = set()
    for area in (250.0, 900.0, 2500.0, 6000.0, 12000.0):
        for seed in range(12):
            for kind in STYLES:
                params = sample_params(kind, area, np.random.default_rng(seed))
                depth = params.corridor_width + params.depth_left + params.depth_right
                shape, wings = make_spine(params, area / (0.85 * depth))
                seen.add(shape)
                if shape == "ring":  # grid lines run through; what is bounded is the pitch
                    ys = sorted({w.p[1] for w in wings if w.p[1] == w.q[1]})
                    longest = ys[1] - ys[0]
                else:
                    longest = max(w.length for w in wings)
                assert longest <= 1.5 * STYLES[kind].max_wing + 1e-6
    assert seen == {"straight", "L", "T", "U", "ring", "comb"}


@pytest.mark.parametrize("kind, area, seed, problem", [
    ("offfice", 300.0, 0, "did you mean 'office'"), ("office", 10.0, 0, "area must be"),
    ("office", math.nan, 0, "area must be"), ("school", 300.0, -1, "seed must be"),
])
def test_bad_arguments(kind, area, seed, problem):
    with pytest.raises(InputError, match=problem):
        generate(kind, area, seed)


def test_cli_generate_writes_world_png_json(tmp_path, capsys):
    assert main(["worlds", "generate", "--kind", "office", "--area", "120", "--seed", "3",
                 "--out", str(tmp_path), "--name", "small"]) == 0
    assert {p.name for p in tmp_path.iterdir()} == {"small.world", "small.png", "small.json"}
    record = json.loads((tmp_path / "small.json").read_text())
    assert record["name"] == "small" and record["version"]
    from slam_predict.world.load import load_plan
    world = load_plan(tmp_path / "small.world")
    again = generate("office", 120.0, 3)
    assert np.array_equal(world.occupied, again.occupied)
    assert np.allclose(world.start_pose, again.start_pose, atol=1e-6)
    assert "wrote" in capsys.readouterr().out


@pytest.mark.parametrize("argv, problem", [
    (["--kind", "house", "--area", "300"], "unknown building kind"),
    (["--kind", "office", "--area", "60000"], "area must be between"),
    (["--kind", "office", "--area", "300", "--resolution", "0"], "resolution must be"),
    (["--kind", "office", "--area", "300", "--name", "../x"], "plain file name"),
])
def test_cli_generate_bad_input_one_line_exit_2(tmp_path, capsys, argv, problem):
    out = tmp_path / "out"
    assert main(["worlds", "generate", *argv, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and problem in err
    assert not out.exists()


def test_cli_generate_out_is_a_file(tmp_path, capsys):
    target = tmp_path / "file"
    target.write_text("x")
    assert main(["worlds", "generate", "--kind", "office", "--area", "100", "--out",
                 str(target)]) == 2
    err = capsys.readouterr().err
    assert str(target) in err and "must be a folder" in err


def test_ground_truth_json_round_trip(tmp_path):
    from slam_predict.world.groundtruth import read_ground_truth

    assert main(["worlds", "generate", "--kind", "school", "--area", "400", "--seed", "5",
                 "--out", str(tmp_path), "--name", "w"]) == 0
    rooms, doors = read_ground_truth(tmp_path / "w.json")
    world = generate("school", 400.0, 5)
    assert [r.id for r in rooms] == [r.id for r in world.rooms]
    assert all(np.allclose(a.polygon, b.polygon, atol=1e-4)
               for a, b in zip(rooms, world.rooms, strict=False))
    assert [d.rooms for d in doors] == [d.rooms for d in world.doors]
    assert all(np.allclose(a.segment, b.segment, atol=1e-4)
               for a, b in zip(doors, world.doors, strict=False))


def test_bad_ground_truth_json(tmp_path):
    from slam_predict.world.groundtruth import read_ground_truth

    path = tmp_path / "gt.json"
    path.write_text('{"rooms": [{"label": "x"}]}')
    with pytest.raises(InputError, match="bad ground-truth record"):
        read_ground_truth(path)
    path.write_text("{")
    with pytest.raises(InputError, match="cannot read"):
        read_ground_truth(path)


SHIPPED = ("tiny", "office_150", "school_300", "office_500", "office_800", "school_1000",
           "office_1500", "school_2500", "office_3000", "school_6000")


@pytest.mark.parametrize("name", SHIPPED)
def test_shipped_world_loads_and_matches_its_metadata(root, name):
    from slam_predict.world.load import load_plan

    record = json.loads((root / "worlds" / f"{name}.json").read_text())
    world = load_plan(root / "worlds" / f"{name}.world")
    assert world.free_area_m2 == pytest.approx(record["area_m2"], abs=0.01)
    assert np.allclose(world.start_pose[:2], record["start_pose"][:2], atol=1e-3)
    assert raster.label_free(~world.occupied)[1] == 1
    assert abs(record["area_m2"] - record["area_requested_m2"]) <= 0.15 * record[
        "area_requested_m2"]
    if name == "tiny":
        assert world.free_area_m2 <= 100.0 and 2 <= len(record["rooms"]) <= 6


@pytest.mark.parametrize("name", ["tiny", "office_500"])
def test_shipped_world_regenerates_exactly(root, name):
    """tools/make_worlds.sh reproduces the shipped bitmaps (determinism from the seed)."""
    from slam_predict.world.bitmap import read_grey

    record = json.loads((root / "worlds" / f"{name}.json").read_text())
    world = generate(record["kind"], record["area_requested_m2"], record["seed"],
                     record["resolution"])
    shipped = read_grey(root / "worlds" / f"{name}.png") < 128
    assert np.array_equal(world.occupied, shipped)
