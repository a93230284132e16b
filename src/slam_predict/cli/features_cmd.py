"""``slam-predict features PLAN``: the floor-plan feature vector of a plan.

Prints a table (name, value, unit), or with ``--json`` one flat JSON object name → value
(``voronoi_traversal_distance`` in m, ``voronoi_traversal_rotation`` in rad, ...).
``--overlay OUT.png`` draws rooms, topology, Voronoi graph and traversal path on the plan,
``--path OUT.csv`` writes the traversal path (x, y in m). ``--world W`` takes the scale and
start pose from Stage world W and the bitmap from PLAN; ``--list`` describes every feature.
"""
from __future__ import annotations

import argparse
import json
import logging
import os
import sys

from slam_predict.cli import plan_checks
from slam_predict.cli.guards import check_out_file
from slam_predict.cli.worlds_cmd import add_plan_arguments
from slam_predict.errors import InputError

NAME = "features"
HELP = "compute the floor-plan features (geometry, topology, Voronoi graph and traversal)"
MODES = ("documented", "thesis_compatible")
LOG = logging.getLogger(__name__)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("plan", metavar="PLAN", nargs="?",
                        help="floor plan: .world, image (.png/.pgm...), map_server .yaml or "
                             "layout .xml")
    add_plan_arguments(parser, plan=False)
    parser.add_argument("--world", metavar="W.world",
                        help="Stage world giving the scale (floorplan size) and start pose for "
                             "the bitmap PLAN")
    parser.add_argument("--config", metavar="YAML",
                        help="feature settings (section 'features'; default: built-in, as "
                             "config/features.yaml)")
    parser.add_argument("--mode", choices=MODES,
                        help="documented algorithms or the seed code's behaviour")
    parser.add_argument("--rooms-source", choices=("segment", "ground_truth"),
                        help="segment the bitmap, or use the plan's ground-truth rooms")
    parser.add_argument("--json", action="store_true", help="print one flat JSON object")
    parser.add_argument("--overlay", metavar="OUT.png", help="write a picture of the extraction")
    parser.add_argument("--path", metavar="OUT.csv", help="write the traversal path (x, y in m)")
    parser.add_argument("--list", action="store_true", help="list the features and exit")
    plan_checks.add_arguments(parser)


def _config(args: argparse.Namespace):
    import dataclasses

    from slam_predict.features.vector import FeaturesConfig
    from slam_predict.learn.config import load_section

    config = (load_section(FeaturesConfig, args.config, "features")
              if args.config else FeaturesConfig())
    if args.mode:
        config = dataclasses.replace(config, mode=args.mode)
    if args.rooms_source:
        config = dataclasses.replace(
            config, rooms=dataclasses.replace(config.rooms, source=args.rooms_source))
    return config


def _world(args: argparse.Namespace):
    from slam_predict.world.load import load_plan

    if args.world is None:
        from slam_predict.cli.worlds_cmd import load_plan_from_args

        return load_plan_from_args(args)
    if args.resolution is not None:
        raise InputError("give either --world or --resolution, not both", args.world)
    if os.path.splitext(args.plan)[1].lower() == ".world":
        raise InputError("PLAN is already a .world file: drop --world", args.plan)
    from slam_predict.world.bitmap import load_occupancy, resample_square
    from slam_predict.world.start import resolve_start

    stage = load_plan(args.world, start=args.start, snap_start=args.snap_start,
                      free_threshold=args.free_threshold)
    occupied = load_occupancy(args.plan, args.free_threshold)
    occupied = resample_square(occupied, stage.size_m, stage.resolution)
    world = stage.replace(occupied=occupied, name=os.path.splitext(os.path.basename(args.plan))[0],
                          rooms=[], doors=[])
    return resolve_start(world, args.start, args.snap_start)


def _print_table(values, registry) -> None:
    width = max(len(name) for name in values)
    for name, value in values.items():
        print(f"{name:<{width}}  {value:14.6g}  {registry.feature(name).unit}")


def _list(registry) -> int:
    for family in registry.families:
        print(f"[{family}]")
        for feature in registry.family(family).features:
            print(f"  {feature.name} ({feature.unit}): {feature.doc}")
    return 0


def _write_path(path: str, xy) -> None:
    from slam_predict.atomic import write_text

    lines = ["x_m,y_m"] + [f"{x:.4f},{y:.4f}" for x, y in xy]
    try:
        write_text(path, "\n".join(lines) + "\n")
    except OSError as exc:
        raise InputError(f"cannot write path ({exc.strerror or exc})", path) from None


def run(args: argparse.Namespace) -> int:
    from slam_predict.features.vector import REGISTRY, compute_with_context, degenerate_reason
    from slam_predict.world.plausibility import unreachable_warning

    if args.list:
        return _list(REGISTRY)
    if not args.plan:
        raise InputError("PLAN is required (or use --list)")
    for option, path in (("--overlay", args.overlay), ("--path", args.path)):
        if path:
            check_out_file(path, args.force, option)
    config = _config(args)
    world = plan_checks.load_checked(_world, args)
    plan_checks.show_progress()
    values, ctx = compute_with_context(world, config)
    reason = degenerate_reason(values)
    if reason:
        raise InputError(reason, world.provenance.get("source") or args.plan)
    note = unreachable_warning(world)
    if note:
        LOG.warning("%s: %s", args.plan, note)
    if args.overlay:
        from slam_predict.features.overlay import write_overlay

        write_overlay(ctx, args.overlay)
    if args.path:
        _write_path(args.path, ctx.path_xy())
    if args.json:
        json.dump(values, sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        _print_table(values, REGISTRY)
    return 0
