"""``slam-predict worlds``: show, convert and validate floor plans / Stage worlds.

Actions (sub-subcommands): ``show PLAN --out PNG``, ``convert PLAN --out X.world``,
``validate PLAN``; ``generate`` and ``import-thesis`` come from
:mod:`slam_predict.cli.worlds_generate` when it is installed (its ``add_generate(subparsers)``
and ``add_import_thesis(subparsers)`` add parsers that ``set_defaults(worlds_run=fn)`` with
``fn(args) -> int``).

Every action that reads a plan takes the same plan options (:func:`add_plan_arguments`), which
other subcommands reuse: ``--resolution``, ``--start X Y [YAW]``, ``--snap-start``,
``--free-threshold``, ``--wall-thickness``, ``--door-width``.
"""
from __future__ import annotations

import argparse
import importlib
import math
import sys

from slam_predict.cli.guards import add_force_argument, check_out_file, check_positive
from slam_predict.errors import InputError

NAME = "worlds"
HELP = "show, convert, validate (and generate) floor plans and Stage worlds"
EXTENSION_MODULE = "slam_predict.cli.worlds_generate"


def add_plan_arguments(parser: argparse.ArgumentParser, plan: bool = True) -> None:
    """The PLAN positional and the options every plan-reading command shares."""
    if plan:
        parser.add_argument("plan", metavar="PLAN",
                            help="floor plan: .world, image (.png/.pgm...), map_server .yaml "
                                 "or layout .xml")
    group = parser.add_argument_group("plan options")
    group.add_argument("--resolution", type=float, metavar="M_PER_PX",
                       help="scale of an image or layout XML (m per pixel)")
    group.add_argument("--start", type=float, nargs="+", metavar="X Y [YAW]",
                       help="start pose: metres in the world frame (origin at the bitmap "
                            "centre, y up) and yaw in degrees")
    group.add_argument("--snap-start", action="store_true",
                       help="move a start pose in (or too close to) a wall to the nearest "
                            "free cell")
    group.add_argument("--free-threshold", type=int, default=250, metavar="GREY",
                       help="image pixels with grey ≥ GREY are free (default 250)")
    group.add_argument("--wall-thickness", type=float, metavar="M",
                       help="layout XML: wall thickness in m")
    group.add_argument("--door-width", type=float, metavar="M",
                       help="layout XML: door width in m")


def load_plan_from_args(args: argparse.Namespace):
    """The World named by ``args.plan`` with the shared plan options applied."""
    from slam_predict.world.load import load_plan

    return load_plan(args.plan, resolution=args.resolution, start=args.start,
                     snap_start=args.snap_start, free_threshold=args.free_threshold,
                     wall_thickness=args.wall_thickness, door_width=args.door_width)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest="worlds_command", metavar="ACTION")
    show = sub.add_parser("show", help="render a plan to a picture (free space, start, scale)",
                          description="Render a plan: free/occupied space, start pose, scale "
                                      "bar, ground-truth rooms and doors when present.")
    add_plan_arguments(show)
    show.add_argument("--out", required=True, metavar="PNG", help="picture to write")
    show.add_argument("--dpi", type=int, default=150, help="resolution of the picture")
    add_force_argument(show)
    show.set_defaults(worlds_run=run_show)

    convert = sub.add_parser("convert", help="write a plan as a Stage world (.world + .png)",
                             description="Write a Stage 4 world file and a 0/255 PNG bitmap "
                                         "beside it; Stage and slam_predict load it alike.")
    add_plan_arguments(convert)
    convert.add_argument("--out", required=True, metavar="X.world", help="world file to write")
    add_force_argument(convert, "replace existing X.world / X.png (default: refuse)")
    convert.set_defaults(worlds_run=run_convert)

    validate = sub.add_parser("validate", help="load a plan and print a one-line summary",
                              description="Load a plan and print size, resolution, free area, "
                                          "start pose and connected free components; exit 0 "
                                          "when it loads, 2 when it does not.")
    add_plan_arguments(validate)
    validate.set_defaults(worlds_run=run_validate)
    _add_extensions(sub)


def _add_extensions(sub) -> None:
    try:
        module = importlib.import_module(EXTENSION_MODULE)
    except ModuleNotFoundError as exc:
        if exc.name == EXTENSION_MODULE:
            return
        raise
    for name in ("add_generate", "add_import_thesis"):
        hook = getattr(module, name, None)
        if hook is not None:
            hook(sub)


def summary(world) -> str:
    """One line: size, resolution, free area, start pose, connected free components."""
    from scipy import ndimage

    from slam_predict.world.raster import FOUR_CONNECTED

    _, count = ndimage.label(~world.occupied, structure=FOUR_CONNECTED)
    rows, cols = world.shape
    width, height = world.size_m
    x, y, yaw = world.start_pose
    return (f"{world.name}: {cols} x {rows} px at {world.resolution:g} m/px "
            f"({width:.2f} x {height:.2f} m), free {world.free_area_m2:.1f} m², "
            f"start ({x:.2f}, {y:.2f}, {math.degrees(yaw):.1f} deg), "
            f"{count} connected free component{'s' if count != 1 else ''}")


def _refuse_overwriting_inputs(out: str, world, what: str) -> None:
    """InputError when writing ``out`` would replace the plan or an image it was read from."""
    import os

    inputs = [world.provenance.get(key) for key in ("source", "bitmap", "image")]
    target = os.path.realpath(out)
    for item in inputs:
        if item and os.path.realpath(item) == target:
            raise InputError(f"{what} would overwrite this input file; choose another --out",
                             item)


def run_show(args: argparse.Namespace) -> int:
    from slam_predict.world.render import render_world

    check_positive(args.dpi, "--dpi")
    check_out_file(args.out, args.force)
    world = load_plan_from_args(args)
    _refuse_overwriting_inputs(args.out, world, "--out")
    render_world(world, args.out, dpi=args.dpi)
    print(f"wrote {args.out}")
    return 0


def run_convert(args: argparse.Namespace) -> int:
    from slam_predict.world.stagefile import write_world

    if not str(args.out).endswith(".world"):
        raise InputError("--out must name a .world file", args.out)
    check_out_file(args.out, args.force)
    check_out_file(str(args.out)[:-len(".world")] + ".png", args.force,
                   "the bitmap written beside --out")
    world = load_plan_from_args(args)
    _refuse_overwriting_inputs(args.out, world, "--out")
    _refuse_overwriting_inputs(str(args.out)[:-len(".world")] + ".png", world,
                               "the bitmap written beside --out")
    path = write_world(world, args.out)
    print(f"wrote {path} and {path.with_suffix('.png').name}: {summary(world)}")
    return 0


def run_validate(args: argparse.Namespace) -> int:
    world = load_plan_from_args(args)
    print(summary(world))
    return 0


def run(args: argparse.Namespace) -> int:
    action = getattr(args, "worlds_run", None) or getattr(args, "func", None)
    if action is None:
        print("slam-predict worlds: choose an action (show, convert, validate, ...); "
              "see 'slam-predict worlds --help'", file=sys.stderr)
        return 2
    return int(action(args) or 0)
