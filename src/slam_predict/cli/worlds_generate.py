"""``slam-predict worlds generate`` and ``slam-predict worlds import-thesis``.

generate: ``--kind office|school --area M2 --seed N --out DIR [--name NAME] [--resolution R]``
writes ``DIR/NAME.world`` + ``NAME.png`` (Stage world, 0/255 bitmap) + ``NAME.json``
(generator metadata, ground-truth rooms and doors). import-thesis: ``CSV --out DIR`` writes
one world (+ ground-truth JSON for layouts) per thesis building with a plan, and the index
``DIR/thesis_worlds.csv``. Every file is written atomically; bad input fails before writing.
"""
from __future__ import annotations

import argparse
import json
import os

from slam_predict.cli.guards import (
    add_force_argument,
    check_out_dir,
    check_out_file,
    check_positive,
    plural,
)
from slam_predict.errors import InputError

INDEX_NAME = "thesis_worlds.csv"


def add_generate(subparsers) -> None:
    """Add the ``generate`` action to the ``worlds`` subparsers."""
    parser = subparsers.add_parser(
        "generate", help="generate an office or school building as a Stage world",
        description="Generate a building (corridor spine, rooms, halls, doors) deterministic "
                    "from its seed; writes NAME.world, NAME.png and NAME.json into DIR. AREA "
                    "is the free floor area in m².")
    parser.add_argument("--kind", required=True, help="office or school")
    parser.add_argument("--area", required=True, type=float, metavar="M2",
                        help="free floor area in m² (50 to 50000)")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    parser.add_argument("--out", required=True, metavar="DIR", help="output folder")
    parser.add_argument("--name", help="world name (default KIND_AREA_sSEED)")
    parser.add_argument("--resolution", type=float, default=0.05, metavar="M_PER_PX",
                        help="bitmap resolution (default 0.05)")
    add_force_argument(parser, "overwrite NAME.world/.png/.json in DIR (default: refuse)")
    parser.set_defaults(worlds_run=run_generate)


def add_import_thesis(subparsers) -> None:
    """Add the ``import-thesis`` action to the ``worlds`` subparsers."""
    parser = subparsers.add_parser(
        "import-thesis", help="build the seed thesis' buildings as Stage worlds",
        description="Build a Stage world at the thesis' scale and start pose for every "
                    "building of environments.csv whose plan is available; writes "
                    f"DIR/<env>.world/.png (+ .json ground truth for layouts) and DIR/"
                    f"{INDEX_NAME}.")
    parser.add_argument("csv", metavar="CSV", help="thesis/environments.csv")
    parser.add_argument("--out", required=True, metavar="DIR", help="output folder")
    parser.add_argument("--plans", metavar="DIR",
                        help="floorplans folder (default: ../floorplans beside the CSV)")
    parser.add_argument("--only", nargs="+", metavar="ENV", help="build only these buildings")
    parser.add_argument("--resolution", type=float, default=0.05, metavar="M_PER_PX",
                        help="bitmap resolution (default 0.05)")
    parser.add_argument("--wall-thickness", type=float, default=0.15, metavar="M",
                        help="layout XML wall thickness (default 0.15)")
    parser.add_argument("--door-width", type=float, default=0.9, metavar="M",
                        help="layout XML door width (default 0.9)")
    add_force_argument(parser, "write into a non-empty DIR, overwriting files of the same "
                               "names (default: refuse)")
    parser.set_defaults(worlds_run=run_import_thesis)


def _safe_name(name: str) -> str:
    if not name or os.sep in name or name.startswith(".") or (os.altsep and os.altsep in name):
        raise InputError(f"--name '{name}' must be a plain file name")
    return name


def run_generate(args: argparse.Namespace) -> int:
    from slam_predict.atomic import write_text
    from slam_predict.world.generator import generate, metadata
    from slam_predict.world.stagefile import write_world

    name = _safe_name(args.name) if args.name is not None else \
        f"{args.kind}_{int(round(args.area))}_s{args.seed}"
    check_out_dir(args.out, force=True)   # files are added to DIR: only those named NAME.*
    for suffix in (".world", ".png", ".json"):
        check_out_file(os.path.join(args.out, name + suffix), args.force)
    world = generate(args.kind, args.area, args.seed, args.resolution, name=name)
    path = write_world(world, os.path.join(args.out, world.name + ".world"))
    record = metadata(world)
    write_text(path.with_suffix(".json"), json.dumps(record, indent=1) + "\n")
    print(f"wrote {path} (+ .png, .json): {record['shape']} {args.kind}, "
          f"free area {record['area_m2']:.1f} m² (requested {args.area:g}), "
          f"{plural(len(world.rooms), 'room')}, {plural(len(world.doors), 'door')}")
    return 0


def run_import_thesis(args: argparse.Namespace) -> int:
    import csv
    import io

    from slam_predict.atomic import write_text
    from slam_predict.errors import did_you_mean
    from slam_predict.world.groundtruth import doors_record, rooms_record
    from slam_predict.world.stagefile import write_world
    from slam_predict.world.thesis import read_environments, thesis_world

    check_out_dir(args.out, args.force)
    for value, option in ((args.resolution, "--resolution"),
                          (args.wall_thickness, "--wall-thickness"),
                          (args.door_width, "--door-width")):
        check_positive(value, option)
    envs = read_environments(args.csv, args.plans)
    if args.only:
        names = [e.env for e in envs]
        for wanted in args.only:
            if wanted not in names:
                raise InputError(f"no building '{wanted}' with a plan" +
                                 did_you_mean(wanted, names), args.csv)
        envs = [e for e in envs if e.env in args.only]
    missing = [e.plan for e in envs if not os.path.isfile(e.plan)]
    if missing:
        raise InputError(f"{len(missing)} plan file(s) not found, e.g. {missing[0]} "
                         "(use --plans DIR)", args.csv)
    rows = []
    for env in envs:
        world, row = thesis_world(env, args.resolution, args.wall_thickness, args.door_width)
        path = write_world(world, os.path.join(args.out, row["world_file"]))
        if world.rooms:
            write_text(path.with_suffix(".json"), json.dumps(
                {"env": env.env, "rooms": rooms_record(world.rooms),
                 "doors": doors_record(world.doors)}, indent=1) + "\n")
        rows.append(row)
        print(f"{env.env}: free {row['free_area_m2']:.1f} m², faithful {row['faithful']}, "
              f"start snapped {row['start_snapped']}")
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=list(rows[0]) if rows else ["env"])
    writer.writeheader()
    writer.writerows(rows)
    write_text(os.path.join(args.out, INDEX_NAME), text.getvalue())
    total = sum(r["free_area_m2"] for r in rows)
    print(f"wrote {plural(len(rows), 'world')} and {INDEX_NAME} into {args.out} "
          f"(free area total {total:.0f} m²)")
    return 0
