"""``slam-predict design``: a robot-configuration design for ``collect --design`` (issue #18).

A maximin Latin hypercube of ``--configs`` robot configurations over laser range (m), field of
view (deg) and the odometry error bounds as multiples of the base robot's (x/y and yaw scales),
dealt over the worlds, ``--points-per-world`` distinct configurations each, every one run
``--replicates`` times (:mod:`slam_predict.collect.robot_design`). Written atomically; an
existing file is only replaced with ``--force``.
"""
from __future__ import annotations

import argparse
from pathlib import Path

from slam_predict.cli.deprecated import add_renamed_option
from slam_predict.cli.guards import add_force_argument, check_at_least, check_out_file, plural
from slam_predict.errors import InputError

NAME = "design"
HELP = "make a robot-configuration design (Latin hypercube) for 'collect --design'"
BOUND_OPTIONS = (("range_max", "--range", "laser range_max, m"),
                 ("fov", "--fov", "laser field of view, deg"),
                 ("odom_xy_scale", "--odom-xy-scale", "x/y odometry error bound, x the base"),
                 ("odom_yaw_scale", "--odom-yaw-scale", "yaw odometry error bound, x the base"))


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("worlds", nargs="+", metavar="WORLD",
                        help="Stage .world files, or folders of them (names = file stems)")
    parser.add_argument("--out", required=True, metavar="YAML", help="design file to write")
    parser.add_argument("--base-robot", default="seed_realistic",
                        metavar="YAML|NAME", help="robot description every configuration starts "
                                             "from (default: the seed study's realistic robot)")
    parser.add_argument("--configs", type=int, default=28, help="configurations (default 28)")
    parser.add_argument("--points-per-world", type=int, default=4,
                        help="distinct configurations per world (default 4)")
    parser.add_argument("--replicates", type=int, default=2,
                        help="runs per world and configuration (default 2)")
    step = parser.add_argument("--angle-step", type=float, default=0.5, metavar="DEG",
                               help="laser angular resolution, deg (default 0.5)")
    add_renamed_option(parser, "--resolution", step)
    parser.add_argument("--seed", type=int, default=0, help="seed of the design (default 0)")
    for factor, option, what in BOUND_OPTIONS:
        parser.add_argument(option, nargs=2, type=float, metavar=("LOW", "HIGH"),
                            help=f"range of the {what}", dest=f"bound_{factor}")
    add_force_argument(parser, "go on where a check would refuse: overwrite an existing --out "
                               "file; use a base robot or make configurations that no real "
                               "robot matches (usually a unit mistake: --fov in radians, "
                               "--range in mm)")


def bounds_of(args: argparse.Namespace) -> dict[str, tuple[float, float]]:
    """The factor bounds: the defaults with the options given; InputError when LOW > HIGH."""
    from slam_predict.collect.robot_design import DEFAULT_BOUNDS

    bounds = dict(DEFAULT_BOUNDS)
    for factor, option, _ in BOUND_OPTIONS:
        given = getattr(args, f"bound_{factor}")
        if given is not None:
            low, high = given
            if not low <= high:
                raise InputError(f"{option} LOW must be <= HIGH, got {low} {high}")
            bounds[factor] = (low, high)
    return bounds


def sources_of(args: argparse.Namespace) -> dict[str, str]:
    """Laser key → the options its design values come from, as the user typed them."""
    def given(factor: str, option: str) -> str:
        value = getattr(args, f"bound_{factor}")
        return option if value is None else f"{option} {value[0]:g} {value[1]:g}"

    return {"laser.fov": given("fov", "--fov"), "laser.range_max": given("range_max", "--range"),
            "laser.samples": f"--angle-step {args.angle_step:g} over {given('fov', '--fov')}"}


def run(args: argparse.Namespace) -> int:
    from slam_predict.cli.collect_cmd import find_worlds
    from slam_predict.collect.robot_design import check_plausible, make_design, write_design
    from slam_predict.robot_file import load_robot

    for option in ("configs", "points_per_world", "replicates"):
        check_at_least(getattr(args, option), 1, "--" + option.replace("_", "-"))
    if not args.angle_step > 0:
        raise InputError(f"--angle-step must be > 0 deg, got {args.angle_step}")
    if args.points_per_world > args.configs:
        raise InputError(f"--points-per-world ({args.points_per_world}) exceeds --configs "
                         f"({args.configs})")
    worlds = find_worlds(args.worlds)
    base = load_robot(args.base_robot, force=args.force)
    check_out_file(args.out, args.force)
    try:   # the design checks that every configuration makes a valid robot
        design = make_design(list(worlds), base, args.configs, args.points_per_world,
                             args.replicates, args.seed, bounds_of(args), args.angle_step)
    except ValueError as exc:
        raise InputError(f"cannot make the design: {exc}", args.base_robot) from None
    check_plausible(design, args.force, sources=sources_of(args))
    write_design(design, args.out)
    runs = len(worlds) * design.runs_per_world
    print(f"{Path(args.out)}: {plural(len(design.configs), 'configuration')} over "
          f"{plural(len(worlds), 'world')}, {design.points_per_world} per world x "
          f"{plural(design.replicates, 'replicate')} = {plural(runs, 'run')}")
    return 0
