"""``slam-predict report DATA``: one self-contained HTML page about a collection campaign.

  slam-predict report DATA [--out report.html] [--models-dir models/] [--worlds DIR] [--title T]

The page holds the campaign overview (worlds, runs, configuration hashes, code versions, stop
reasons, simulated and wall time), the per-building summary (error components in m, rad and
deg), per world the final SLAM map of a representative run with the ground-truth and SLAM paths
and the per-run table; with ``--models-dir`` also the model cards (scores) and the models'
predictions for the campaign's worlds next to the measured values. Images are embedded as PNG,
there is no script and no external file. Missing pieces (a run without map, a world file that
cannot be found) are listed on the page.
"""
from __future__ import annotations

import argparse
import os

from slam_predict.cli.deprecated import add_renamed_option
from slam_predict.cli.guards import add_force_argument, check_out_file

NAME = "report"
HELP = "write one self-contained HTML report of a collection campaign (and model predictions)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("data", metavar="DATA", help="campaign folder written by "
                                                     "'slam-predict collect'")
    parser.add_argument("--out", default="report.html", metavar="HTML",
                        help="page to write (default report.html)")
    models = parser.add_argument(
        "--models-dir", metavar="DIR",
        help="a model folder or a folder of them (e.g. models/): adds the model cards and their "
             "predictions for the campaign's worlds")
    add_renamed_option(parser, "--models", models)
    parser.add_argument("--worlds", metavar="DIR",
                        help="folder of the campaign's <world>.world files, searched first "
                             "for the plans the models predict from (default: the runs' "
                             "recorded world_file, then the shipped worlds/)")
    parser.add_argument("--title", help="page title (default: from DATA's name)")
    add_force_argument(parser)


def run(args: argparse.Namespace) -> int:
    from slam_predict.atomic import write_text
    from slam_predict.errors import InputError
    from slam_predict.report.build import build_report

    check_out_file(args.out, args.force)
    if args.worlds is not None and not os.path.isdir(args.worlds):
        raise InputError("--worlds: not a folder", args.worlds)
    text = build_report(args.data, args.models_dir, args.title, worlds_dir=args.worlds)
    try:
        write_text(args.out, text)
    except OSError as exc:
        raise InputError(f"cannot write the report ({exc.strerror or exc})", args.out) from None
    print(f"report: {args.out} ({len(text) / 1e6:.1f} MB)")
    return 0
