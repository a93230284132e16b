"""Stage world → World mapping, the writer, and write → read round trips."""
from __future__ import annotations

import math
import re
from pathlib import Path

import cv2
import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.world.model import LaserSpec, RobotSpec, World
from slam_predict.world.stagefile import read_world, write_world

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = sorted(ROOT.glob("worlds/*.world")) + [ROOT / "tests/data/world_map/tiny.world"]
DEG = math.pi / 180.0


def random_world(rng: np.random.Generator, name: str = "w") -> World:
    """An enclosed random world: a walled box with random interior walls and specs."""
    rows, cols = rng.integers(20, 70, size=2)
    occ = np.ones((rows, cols), bool)
    occ[2:-2, 2:-2] = False
    for _ in range(rng.integers(0, 6)):
        r, c = rng.integers(2, rows - 2), rng.integers(2, cols - 2)
        occ[r:r + rng.integers(1, 3), c:c + rng.integers(1, 15)] = True
    res = float(rng.choice([0.05, 0.025, 0.1, 0.037]))
    world = World(name=name, occupied=occ, resolution=res,
                  origin=(float(rng.uniform(-5, 5)), float(rng.uniform(-5, 5))),
                  robot=RobotSpec(footprint_side=float(rng.uniform(0.2, 0.6)),
                                  max_vel_x=float(rng.uniform(0.3, 1.5)),
                                  max_vel_theta=float(rng.uniform(0.5, 2.0)),
                                  max_acc_x=float(rng.uniform(0.5, 3)),
                                  max_acc_theta=float(rng.uniform(0, 3)),
                                  odom_error=(0.01, 0.02, 0.0, float(rng.uniform(0, 0.1))),
                                  localization=str(rng.choice(["odom", "gps"])),
                                  drive=str(rng.choice(["diff", "omni"]))),
                  laser=LaserSpec(fov=float(rng.uniform(1, 6)), samples=int(rng.integers(2, 1100)),
                                  range_min=0.1, range_max=float(rng.uniform(5, 80)),
                                  rate_hz=float(rng.choice([10.0, 20.0, 5.0, 40.0])),
                                  pose=(0.1, -0.02, float(rng.uniform(-1, 1))),
                                  noise_std=float(rng.choice([0.0, 0.01]))),
                  interval_sim=float(rng.choice([0.1, 0.05, 0.02])))
    free = np.argwhere(~occ)
    r, c = free[rng.integers(len(free))]
    x, y = world.cell_to_world((r, c))
    return world.replace(start_pose=np.array([x, y, float(rng.uniform(-math.pi, math.pi))]))


def assert_same_world(a: World, b: World) -> None:
    assert a.shape == b.shape
    assert np.array_equal(a.occupied, b.occupied)
    assert abs(a.resolution - b.resolution) <= 1e-9
    assert a.origin == pytest.approx(b.origin, abs=1e-9)
    assert a.start_pose[:2] == pytest.approx(b.start_pose[:2], abs=1e-9)
    assert abs(math.remainder(a.start_pose[2] - b.start_pose[2], 2 * math.pi)) < 1e-9
    assert a.interval_sim == pytest.approx(b.interval_sim, abs=1e-12)
    for field in ("footprint_side", "max_vel_x", "max_vel_theta", "max_acc_x", "max_acc_theta"):
        assert getattr(a.robot, field) == pytest.approx(getattr(b.robot, field), abs=1e-12)
    assert a.robot.odom_error == pytest.approx(b.robot.odom_error, abs=1e-12)
    assert (a.robot.localization, a.robot.drive) == (b.robot.localization, b.robot.drive)
    assert a.laser.samples == b.laser.samples
    for field in ("fov", "range_min", "range_max", "rate_hz", "noise_std"):
        assert getattr(a.laser, field) == pytest.approx(getattr(b.laser, field), abs=1e-12)
    assert a.laser.pose == pytest.approx(b.laser.pose, abs=1e-12)


@pytest.mark.parametrize("seed", range(12))
def test_round_trip_random_worlds(tmp_path, seed):
    world = random_world(np.random.default_rng(seed), name=f"rand{seed}")
    path = write_world(world, tmp_path / "out" / f"rand{seed}.world")
    back = read_world(path)
    assert_same_world(world, back)
    assert back.provenance["start_given"] is True and back.provenance["defaults"] == []
    assert sorted(p.name for p in path.parent.iterdir()) == [f"rand{seed}.png",
                                                            f"rand{seed}.world"]


@pytest.mark.parametrize("path", SHIPPED, ids=[p.stem for p in SHIPPED])
def test_round_trip_shipped_worlds(tmp_path, path):
    world = read_world(path)
    again = read_world(write_world(world, tmp_path / f"{path.stem}.world"))
    assert_same_world(world, again)


def test_written_bitmap_is_clean_and_stage_reads_it_the_same(tmp_path):
    world = random_world(np.random.default_rng(5))
    path = write_world(world, tmp_path / "w.world")
    grey = cv2.imread(str(path.with_suffix(".png")), cv2.IMREAD_UNCHANGED)
    assert grey.dtype == np.uint8 and grey.ndim == 2
    assert set(np.unique(grey)) <= {0, 255}
    assert np.array_equal(grey <= 127, world.occupied)   # Stage: first channel ≤ 127 = obstacle


def test_written_file_is_stage_syntax(tmp_path):
    world = random_world(np.random.default_rng(1)).replace(resolution=1e-3 * 37)
    text = write_world(world, tmp_path / "w").read_text()
    assert (tmp_path / "w.world").exists()
    assert not re.search(r"\d[eE][-+]?\d", text), "Stage cannot read exponents"
    for line in text.splitlines():
        assert line.count("[") == line.count("]"), "tuples must stay on one line"
    assert re.search(r"^interval_sim \d", text, re.M)
    assert re.search(r"^resolution 0\.025$", text, re.M)
    assert 'bitmap "w.png"' in text and "floorplan" in text and "sensor" in text


def write_bitmap(path: Path, grey: np.ndarray) -> Path:
    cv2.imwrite(str(path), grey)
    return path


def test_uneven_size_resampled_to_square_pixels(tmp_path):
    grey = np.zeros((30, 40), np.uint8)
    grey[2:-2, 2:-2] = 255
    grey[10:20, 20] = 0   # a 1 px wall
    write_bitmap(tmp_path / "m.png", grey)
    (tmp_path / "a.world").write_text('model( bitmap "m.png" size [4 6 1] )\n')
    world = read_world(tmp_path / "a.world")
    assert world.resolution == pytest.approx(0.1)   # the finer of 0.1 and 0.2 m/px
    assert world.shape == (60, 40) and world.provenance["resampled"] is True
    # slow reference: each target cell looks up the source pixel under its centre
    rows, cols = world.shape
    src_occ = grey < 250
    for r in range(rows):
        for c in range(cols):
            x, y = world.cell_to_world((r, c))
            sc, sr = int((x + 2.0) / 0.1), int((3.0 - y) / 0.2)
            assert world.occupied[r, c] == src_occ[sr, sc]


def test_grey_outside_and_antialiased_walls_follow_our_threshold(tmp_path):
    grey = np.full((30, 40), 190, np.uint8)     # grey outside (ipa style)
    grey[3:-3, 3:-3] = 255
    grey[3:-3, 3] = 0
    grey[3:-3, 4] = 128                          # anti-aliased edge: obstacle for us
    write_bitmap(tmp_path / "m.png", grey)
    (tmp_path / "a.world").write_text('model( bitmap "m.png" size [4 3 1] )\n')
    world = read_world(tmp_path / "a.world")
    assert np.array_equal(world.occupied, grey < 250)


def test_box_block_and_bitmap_obstacles_are_drawn(tmp_path):
    grey = np.zeros((40, 40), np.uint8)
    grey[1:-1, 1:-1] = 255
    write_bitmap(tmp_path / "m.png", grey)
    small = np.full((4, 4), 255, np.uint8)
    small[:, :2] = 0
    write_bitmap(tmp_path / "s.png", small)
    (tmp_path / "a.world").write_text(
        'model( bitmap "m.png" size [4 4 1] )\n'
        "model( pose [1 1 0 0] size [0.4 0.2 0.5] )\n"                 # a box
        "model( pose [-1 1 0 0] size [0.4 0.4 0.5] obstacle_return 0 )\n"  # invisible
        'model( pose [-1 -1 0 0] size [0.4 0.4 0.5] bitmap "s.png" )\n'   # left half black
        "model( pose [1 -1 0 0] size [0.4 0.4 1] block( points 3 point[0] [0 0] "
        "point[1] [1 0] point[2] [0 1] z [0 1] ) )\n"
        "position( pose [0 0 0 0] size [0.5 0.5 0.5] )\n")
    world = read_world(tmp_path / "a.world")
    occ = lambda x, y: bool(~world.is_free_at(np.array([x, y])))  # noqa: E731
    assert occ(1.0, 1.0) and occ(1.15, 1.05) and not occ(1.25, 1.0) and not occ(1.0, 1.15)
    assert not occ(-1.0, 1.0)
    assert occ(-1.15, -1.0) and not occ(-0.9, -1.0)
    assert occ(0.85, -1.15) and not occ(1.15, -0.85)        # triangle: lower-left half
    assert not occ(0.0, 0.0)                                 # the robot is not an obstacle


def test_robot_defaults_follow_stage(tmp_path):
    write_bitmap(tmp_path / "m.png", np.pad(np.full((20, 20), 255, np.uint8), 1))
    (tmp_path / "a.world").write_text('model( bitmap "m.png" size [2.2 2.2 1] )\n'
                                      "position( pose [0.1 0.2 0 0] )\n"
                                      "position( pose [-0.5 -0.5 0 0] )\n")
    world = read_world(tmp_path / "a.world")
    assert world.start_pose == pytest.approx([0.1, 0.2, 0.0])    # the first position model
    assert world.robot.localization == "gps"                      # Stage's default
    assert world.robot.max_vel_x == 1.0 and world.robot.max_vel_theta == pytest.approx(90 * DEG)
    assert set(world.provenance["defaults"]) == {"size", "acceleration_bounds", "odom_error",
                                                 "laser"}
    assert world.laser == LaserSpec()


@pytest.mark.parametrize("text, fragment", [
    ('model( bitmap "missing.png" size [4 3 1] )\n', "bitmap 'missing.png' not found"),
    ('model( bitmap "m.png" )\n', "has no 'size [W H Z]'"),
    ('model( bitmap "m.png" size [0 3 1] )\n', "size of model must be > 0"),
    ('model( bitmap "m.png" size [4 -3 1] )\n', "size of model must be > 0"),
    ("model( size [4 3 1] )\n", "no floor plan"),
    ('model( bitmap "m.png" size [4 3 1] pose [0 0 0 45] )\n', "only multiples of 90 deg"),
    ('model( bitmap "m.png" size [4 3 1] )\nposition( localization "slam" )\n',
     "localization \"slam\" is not one of"),
    ('interval_sim 0\nmodel( bitmap "m.png" size [4 3 1] )\n', "interval_sim must be > 0"),
    ('model( bitmap "m.png" size [4 3 1] )\nposition( ranger( sensor( samples 0 ) ) )\n',
     "samples ≥ 1"),
])
def test_world_content_errors(tmp_path, text, fragment):
    write_bitmap(tmp_path / "m.png", np.pad(np.full((20, 20), 255, np.uint8), 1))
    (tmp_path / "a.world").write_text(text)
    with pytest.raises(InputError) as err:
        read_world(tmp_path / "a.world")
    assert fragment in err.value.problem
    assert err.value.path in (str(tmp_path / "a.world"),)


def test_stage_ros_style_world(tmp_path):
    """Includes in a subfolder, a 'block' macro used as a box (as stage_ros' willow world
    does), a ranger carrying a decorative model, a fiducial child, a floor plan turned by 90°."""
    grey = np.zeros((10, 20), np.uint8)          # 2 m x 1 m in the model frame
    grey[1:-1, 1:-1] = 255
    grey[2:4, 3:5] = 0                           # pillar around local (-0.6, 0.2)
    (tmp_path / "maps").mkdir()
    cv2.imwrite(str(tmp_path / "maps" / "room.png"), grey)
    (tmp_path / "include").mkdir()
    (tmp_path / "include" / "robot.inc").write_text(
        "define scanner ranger ( sensor( range [0 8] fov 240 samples 481 )\n"
        "  model( size [0.07 0.07 0.05] color \"blue\" ) )\n"
        "define reader fiducial ( range_max 8 fov 270 model( size [0.1 0.1 0.1] ) )\n"
        "define bot_base position ( drive \"diff\" localization \"gps\"\n"
        "  localization_origin [0 0 0 0] velocity_bounds [-1 1 0 0 0 0 -45 45]\n"
        "  acceleration_bounds [-0.5 0.5 0 0 0 0 -45 45] )\n"
        "define bot bot_base ( size [0.44 0.38 0.22] origin [-0.04 0 0 0] mass 23.0 )\n")
    (tmp_path / "a.world").write_text(
        'include "include/robot.inc"\n'
        "define block model ( size [0.2 0.2 0.5] gui_nose 0 )\n"
        "define floorplan model ( color \"gray30\" boundary 1 laser_return 1 )\n"
        "resolution 0.02\ninterval_sim 100  # ms\n"
        "window ( size [ 745.000 448.000 ] rotate [ 0.000 -1.560 ] scale 28.806 )\n"
        'floorplan ( name "room" bitmap "maps/room.png" size [2.0 1.0 0.5]\n'
        "  pose [ 3 4 0 90.000 ] )\n"
        'bot( pose [ 3.1 4.4 0 180.000 ] name "era" color "blue"\n'
        "     scanner( pose [ 0.05 0 0 0 ] ) reader( ) )\n"
        'block( pose [ 3.15 3.3 0 180.000 ] color "red" )\n')
    world = read_world(tmp_path / "a.world")
    assert world.shape == (20, 10) and world.resolution == pytest.approx(0.1)
    assert world.origin == pytest.approx((3.0, 4.0))
    occ = lambda x, y: bool(~world.is_free_at(np.array([x, y])))  # noqa: E731
    assert occ(3.0 - 0.2, 4.0 - 0.6)             # pillar turned counter-clockwise by 90°
    assert not occ(3.0 + 0.2, 4.0 + 0.6)         # ... not mirrored
    assert occ(3.15, 3.3) and not occ(3.15, 3.5)  # the 'block' box
    assert not occ(3.1, 4.4)                     # the robot is not an obstacle
    assert world.start_pose == pytest.approx([3.1, 4.4, math.pi])
    assert world.robot.footprint_side == pytest.approx(0.44)
    assert world.robot.max_vel_theta == pytest.approx(45 * DEG)
    assert world.robot.max_acc_x == 0.5 and world.robot.localization == "gps"
    assert world.laser.samples == 481 and world.laser.pose == pytest.approx((0.05, 0.0, 0.0))
    assert world.provenance["floorplan_quarter_turns"] == 1
