"""``slam-predict explore PLAN --map-source perfect|SLAM --seed N --out DIR``: frontier
exploration of a floor plan in closed loop (simulator + map source + move_base + explorer), in
sim time, without ROS.

PLAN is a Stage .world, a PNG/PGM image (with ``--resolution``) or a layout XML. Writes
DIR/explore.json (coverage of the reachable free area, sim and wall time, distance, rotation,
stalls, stop reason, goals, timings) and DIR/explore.png (the final map with the path).
Settings come from config/ (move_base, costmaps, planners, explore, closed_loop, robot and, for
a SLAM back-end such as ``gmapping``, its ``<name>.yaml``); ``--config-dir`` points elsewhere.
The map-source choices are ``perfect`` and :func:`slam_predict.slam.available`.
"""
from __future__ import annotations

import argparse

from slam_predict.cli.guards import add_force_argument, check_out_dir, check_positive, plural

NAME = "explore"
HELP = "explore a floor plan in closed loop (simulator, map source, move_base, frontiers)"


def _non_negative_int(text: str) -> int:
    value = int(text)
    if value < 0:
        raise argparse.ArgumentTypeError("must be >= 0")
    return value


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from slam_predict.explore import map_sources

    parser.add_argument("plan", metavar="PLAN", help=".world, PNG/PGM (with --resolution) or "
                                                     "layout XML")
    parser.add_argument("--map-source", choices=map_sources(), default="perfect",
                        help="map from the true poses (perfect) or from a SLAM back-end "
                             "(default perfect)")
    parser.add_argument("--slam", metavar="NAME",
                        help="map from this SLAM back-end: gmapping or karto (slam_toolbox: the "
                             "same); another spelling of --map-source NAME")
    parser.add_argument("--seed", type=_non_negative_int, default=0,
                        help="random seed (default 0)")
    parser.add_argument("--out", required=True, metavar="DIR", help="output folder")
    add_force_argument(parser)
    parser.add_argument("--resolution", type=float, metavar="R", help="m/px of an image plan")
    parser.add_argument("--start", type=float, nargs="+", metavar="V",
                        help="start pose X Y [YAW] (m, m, degrees); default: the world's, else "
                             "the free cell of largest clearance")
    parser.add_argument("--snap-start", action="store_true",
                        help="move a start pose in or too close to a wall to the nearest free cell")
    parser.add_argument("--max-sim-time", type=float, metavar="S",
                        help="stop after S s of sim time (default: closed_loop.yaml, 10800)")
    parser.add_argument("--strategy", choices=("thesis", "nearest", "explore_lite"),
                        help="frontier choice (default: explore.yaml)")
    parser.add_argument("--config-dir", metavar="DIR",
                        help="folder with the YAML settings (default: the project's config/)")


def run(args: argparse.Namespace) -> int:
    import dataclasses
    import os

    from slam_predict.atomic import atomic_dir
    from slam_predict.errors import InputError
    from slam_predict.explore import run as runner
    from slam_predict.world.load import load_plan

    check_positive(args.max_sim_time, "--max-sim-time")
    if args.slam is not None:
        from slam_predict.slam import canonical_name
        name = canonical_name(args.slam)
        if args.map_source not in ("perfect", name):
            raise InputError(f"--slam {args.slam} contradicts --map-source {args.map_source}")
        args.map_source = name
    check_out_dir(args.out, args.force, inputs=(args.plan, args.config_dir))
    config_dir = args.config_dir or runner.DEFAULT_CONFIG_DIR
    if not os.path.isdir(config_dir):
        raise InputError("config folder not found", config_dir)
    settings = runner.load_explore_settings(config_dir, args.map_source)
    if args.strategy:
        settings.explore = dataclasses.replace(settings.explore, strategy=args.strategy)
    world = load_plan(args.plan, resolution=args.resolution, start=args.start,
                      snap_start=args.snap_start)
    summary, loop = runner.explore_world(world, args.seed, settings, args.map_source,
                                         args.max_sim_time)
    with atomic_dir(args.out) as tmp:
        runner.write_outputs(tmp, summary, loop)
    out = args.out
    print(f"{world.name}: coverage {summary['coverage']:.1%} of {summary['reachable_free_m2']} m² "
          f"in {summary['sim_duration_s'] / 60:.1f} min sim ({summary['wall_time_s']:.0f} s wall), "
          f"{summary['distance_m']:.0f} m, {plural(summary['stalls'], 'stall')}, "
          f"stop: {summary['stop_reason']} -> {out}")
    return 0
