"""Stage world-file syntax: comments, strings, tuples, include, define, nesting, units."""
from __future__ import annotations

import math
import textwrap
from pathlib import Path

import cv2
import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.world.stagefile import parse_world_file, read_world
from slam_predict.world.stagefile.lexer import tokenize

DEG = math.pi / 180.0


def box_png(path: Path, cols: int = 40, rows: int = 30) -> Path:
    """A free box with a 2 px black border, as a clean 0/255 PNG."""
    grey = np.zeros((rows, cols), np.uint8)
    grey[2:-2, 2:-2] = 255
    cv2.imwrite(str(path), grey)
    return path


def write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(textwrap.dedent(text))
    return path


FLOOR = 'floorplan( bitmap "box.png" size [4 3 1] pose [0 0 0 0] )\n'
FLOOR_DEFINE = "define floorplan model ( boundary 1 gui_nose 0 )\n"


@pytest.fixture
def folder(tmp_path):
    box_png(tmp_path / "box.png")
    return tmp_path


def test_comments_strings_and_tuples(folder):
    world = write(folder / "a.world", """\
        # a comment line
        name "with # hash inside"   # trailing comment
        interval_sim 50
        define floorplan model ( color "gray30" )  # define, then a comment
        floorplan( bitmap "box.png" size [ 4 3 1 ] pose [0 0 0 0]
                   name "floor" )
        """)
    root = parse_world_file(world)
    assert root.props["name"].values[0].text == "with # hash inside"
    floor = root.children[0]
    assert floor.type == "model" and floor.macros == ("floorplan",)
    assert [t.text for t in floor.props["size"].values] == ["4", "3", "1"]
    assert read_world(world).interval_sim == pytest.approx(0.05)


def test_tokens_keep_file_and_line(folder):
    world = write(folder / "a.world", 'name "x"\n\n  pose [1 2]\n')
    toks = tokenize(world)
    assert [(t.text, t.line) for t in toks] == [
        ("name", 1), ("x", 1), ("pose", 3), ("[", 3), ("1", 3), ("2", 3), ("]", 3)]


def test_include_relative_to_including_file(folder):
    write(folder / "inc" / "robots.inc", 'include "sensors/laser.inc"\n'
          "define bot position ( size [0.5 0.5 0.2] las( ) )\n")
    write(folder / "inc" / "sensors" / "laser.inc",
          "define las ranger ( sensor( range [0 20] fov 180 samples 181 ) )\n")
    world = write(folder / "a.world", 'include "inc/robots.inc"\n' + FLOOR_DEFINE + FLOOR
                  + "bot( pose [1 0.5 0 90] )\n")
    w = read_world(world)
    assert w.laser.samples == 181 and w.laser.fov == pytest.approx(math.pi)
    assert w.robot.footprint_side == pytest.approx(0.5)
    assert w.start_pose == pytest.approx([1.0, 0.5, math.pi / 2])


def test_include_falls_back_to_world_folder_like_stage(folder):
    write(folder / "inc" / "a.inc", 'include "b.inc"\n')   # b.inc is beside the world file
    write(folder / "b.inc", FLOOR_DEFINE)
    world = write(folder / "a.world", 'include "inc/a.inc"\n' + FLOOR)
    assert read_world(world).shape == (30, 40)


def test_define_inheritance_multi_level_and_override(folder):
    world = write(folder / "a.world", FLOOR_DEFINE + FLOOR + """\
        define base_robot position ( size [0.4 0.4 0.2] localization "gps" drive "diff"
                                     odom_error [0.1 0.1 0 1] )
        define mid_robot base_robot ( localization "odom" odom_error [0.02 0.03 0 4] )
        define top_robot mid_robot ( size [0.6 0.5 0.2] )
        top_robot( pose [0 0 0 0] odom_error [0.05 0.06 0 8] )
        """)
    root = parse_world_file(world)
    robot = [e for e, _ in root.walk() if e.type == "position"][0]
    assert robot.macros == ("top_robot", "mid_robot", "base_robot")
    w = read_world(world)
    assert w.robot.localization == "odom"          # from mid_robot, overriding base_robot
    assert w.robot.footprint_side == pytest.approx(0.6)   # from top_robot
    assert w.robot.odom_error == pytest.approx((0.05, 0.06, 0.0, 8 * DEG))  # instance wins
    assert w.robot.drive == "diff"                 # inherited from the deepest base


def test_macro_children_accumulate_and_macro_defined_later(folder):
    world = write(folder / "a.world", FLOOR_DEFINE + FLOOR + """\
        define bot position ( hok( pose [0.1 0 0 0] ) )
        define hok ranger ( sensor( range [0.1 30] fov 270 samples 1081 noise [0.0004 0 0] ) )
        bot( pose [0 0 0 0] )
        """)
    w = read_world(world)
    assert w.laser.samples == 1081
    assert w.laser.range_min == pytest.approx(0.1) and w.laser.range_max == pytest.approx(30)
    assert w.laser.pose == pytest.approx((0.1, 0.0, 0.0))
    assert w.laser.noise_std == pytest.approx(0.02)


def test_nested_poses_are_relative_to_the_parent(folder):
    world = write(folder / "a.world", FLOOR_DEFINE + """\
        model( pose [1 0 0 90] size [0.01 0.01 0.01]
          model( pose [0.5 0 0 0] size [0.01 0.01 0.01]
            position( pose [0.2 0 0 90]
              ranger( pose [0.1 0 0 -90] sensor( pose [0.05 0 0 45] fov 90 samples 2 ) ) ) ) )
        """ + FLOOR)
    w = read_world(world)
    # (1,0,90°) ⊕ (0.5,0,0) = (1, 0.5, 90°); ⊕ (0.2,0,90°) = (1, 0.7, 180°)
    assert w.start_pose[:2] == pytest.approx([1.0, 0.7])
    assert abs(math.remainder(w.start_pose[2] - math.pi, 2 * math.pi)) < 1e-9
    # laser on the robot: (0.1,0,-90°) ⊕ (0.05,0,45°) = (0.1, -0.05, -45°)
    assert w.laser.pose == pytest.approx((0.1, -0.05, -45 * DEG))


def test_degrees_converted_exactly_as_stage(folder):
    world = write(folder / "a.world", FLOOR_DEFINE + FLOOR + """\
        position( pose [0 0 0 30] odom_error [0.01 0.02 0.5 3]
                  velocity_bounds [-0.5 0.7 -1 1 -1 1 -45 60]
                  acceleration_bounds [-1 2 -1 1 -1 1 -10 20]
                  ranger( sensor( fov 240 samples 10 range [0 10] ) ) )
        """)
    w = read_world(world)
    assert w.start_pose[2] == 30 * DEG
    assert w.robot.odom_error == (0.01, 0.02, 0.5, 3 * DEG)   # z untouched, yaw converted
    assert w.robot.max_vel_x == 0.7 and w.robot.max_vel_theta == 60 * DEG
    assert w.robot.max_acc_x == 2.0 and w.robot.max_acc_theta == 20 * DEG
    assert w.laser.fov == 240 * DEG


def test_unit_angle_radians_and_unit_length_cm(folder):
    world = write(folder / "a.world", 'unit_angle "radians"\nunit_length "cm"\n' + FLOOR_DEFINE
                  + 'floorplan( bitmap "box.png" size [400 300 100] )\n'
                  + "position( pose [50 -20 0 1.5] )\n")
    w = read_world(world)
    assert w.resolution == pytest.approx(0.1)
    assert w.start_pose == pytest.approx([0.5, -0.2, 1.5])


def test_window_and_gui_properties_are_ignored(folder):
    world = write(folder / "a.world", """\
        speedup -1
        paused 0
        show_clock 1
        window( size [635 666] scale 28.8 center [0 0] rotate [0 0] show_data 1 anything 3 )
        """ + FLOOR_DEFINE + FLOOR)
    w = read_world(world)
    assert w.provenance["stage"]["speedup"] == -1
    assert w.provenance["start_given"] is False


def test_world_properties_recorded(folder):
    world = write(folder / "a.world", "interval_sim 25\nresolution 0.01\nquit_time 3600\n"
                  "threads 2\n" + FLOOR_DEFINE + FLOOR)
    w = read_world(world)
    assert w.interval_sim == pytest.approx(0.025)
    assert w.provenance["stage"] == {"interval_sim_ms": 25.0, "resolution": 0.01,
                                     "speedup": 1.0, "quit_time": 3600.0, "threads": 2}
    assert w.provenance["size_m"] == [4.0, 3.0]
    assert w.provenance["bitmap"] == str(folder / "box.png")


@pytest.mark.parametrize("text, line, fragment", [
    ("name \"ok\"\nfloorplan( bitmap \"box.png\" size [4 3 1]\n", 2, "missing ')'"),
    ("interval_sim 100\n\nname \"unterminated\n", 3, "unterminated string"),
    ("interval_sim 1e-3\n", 1, "exponent"),
    ("model( pose [0 0\n 0 0] )\n", 1, "on the line where it starts"),
    ("model( drive diff )\n", 1, 'quote string values: drive "diff"'),
    ("model( pose[0 0 0 0] )\n", 1, "put a space before '['"),
    ("\n\ninterval_sim 100 )\n", 3, "unexpected ')'"),
    ("model( size [1 2 3] ) @\n", 1, "unexpected character '@'"),
    ("define floorplan model\n", 1, "define NEW BASE"),
    ("model( define x model ( ) )\n", 1, "only allowed at the top level"),
    ("sensor( fov 10 )\n", 1, "a sensor cannot be placed in the top level"),
    ("define a b ( )\ndefine b a ( )\na( )\n", 1, "recursive define"),
])
def test_syntax_errors_name_file_and_line(folder, text, line, fragment):
    world = write(folder / "bad.world", text)
    with pytest.raises(InputError) as err:
        read_world(world)
    assert err.value.path == str(world) and err.value.line == line
    assert fragment in err.value.problem


def test_error_inside_include_names_the_include(folder):
    write(folder / "inc.inc", "\n\ninterval_sim [1 2\n")
    world = write(folder / "a.world", 'include "inc.inc"\n')
    with pytest.raises(InputError) as err:
        read_world(world)
    assert err.value.path == str(folder / "inc.inc") and err.value.line == 3


def test_unknown_type_and_property_suggest_a_fix(folder):
    world = write(folder / "a.world", FLOOR_DEFINE + FLOOR + "postion( pose [0 0 0 0] )\n")
    with pytest.raises(InputError, match=r"unknown model type 'postion' \(did you mean "
                                         r"'position'\?\)") as err:
        read_world(world)
    assert err.value.line == 3
    world = write(folder / "b.world", FLOOR_DEFINE + FLOOR
                  + "position( pose [0 0 0 0]\n  odom_eror [0 0 0 0] )\n")
    with pytest.raises(InputError, match=r"unknown property 'odom_eror' in position \(position\)"
                                         r" \(did you mean 'odom_error'\?\)") as err:
        read_world(world)
    assert err.value.line == 4
    world = write(folder / "c.world", "intervall_sim 100\n")
    with pytest.raises(InputError, match="did you mean 'interval_sim'"):
        read_world(world)
    world = write(folder / "d.world", "laser( fov 180 )\n")
    with pytest.raises(InputError, match="Stage 4 has no 'laser' type"):
        read_world(world)


def test_include_errors(folder):
    world = write(folder / "a.world", '\ninclude "nope.inc"\n')
    with pytest.raises(InputError, match="included file 'nope.inc' not found") as err:
        read_world(world)
    assert err.value.line == 2
    write(folder / "x.inc", 'include "y.inc"\n')
    write(folder / "y.inc", 'include "x.inc"\n')
    world = write(folder / "b.world", 'include "x.inc"\n')
    with pytest.raises(InputError, match="include cycle"):
        read_world(world)


def test_short_tuples_and_bad_numbers(folder):
    world = write(folder / "a.world", FLOOR_DEFINE + FLOOR + "position( pose [1 2 3] )\n")
    with pytest.raises(InputError, match="'pose' needs 4 values, got 3"):
        read_world(world)
    world = write(folder / "b.world", FLOOR_DEFINE + FLOOR
                  + 'position( odom_error [0 0 0 "x"] )\n')
    with pytest.raises(InputError, match="needs a number"):
        read_world(world)
    world = write(folder / "c.world", "interval_sim 1.2.3\n" + FLOOR_DEFINE + FLOOR)
    with pytest.raises(InputError, match="'1.2.3' is not a number"):
        read_world(world)
