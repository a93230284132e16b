"""Plan checks shared by ``predict`` and ``features``: size guard, plausible scale, progress.

``--max-pixels N`` sets the image size guard (:func:`slam_predict.world.bitmap.pixel_limit`,
checked from the image header before decoding); ``--force`` accepts a plan whose free area or
extent no building has (:func:`slam_predict.world.plausibility.check_scale`). Progress of the
feature extraction (logger ``slam_predict.features.progress``) goes to stderr when stderr is a
terminal or with ``-v``.
"""
from __future__ import annotations

import argparse
import logging
import sys
from collections.abc import Callable

PROGRESS_LOGGER = "slam_predict.features.progress"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """``--force`` and ``--max-pixels``."""
    from slam_predict.world.bitmap import DEFAULT_MAX_PIXELS

    group = parser.add_argument_group("plan checks")
    group.add_argument("--force", action="store_true",
                       help="go on where a check would refuse: use a plan whose free area or "
                            "extent is outside what buildings have (10–100,000 m², ≤ 2 km), "
                            "usually a wrong --resolution, or a robot file that no real robot "
                            "matches (usually a unit mistake); overwrite existing output files")
    group.add_argument("--max-pixels", type=int, metavar="N",
                       help=f"refuse images of more than N pixels before decoding them "
                            f"(default {DEFAULT_MAX_PIXELS:,}; about 33 bytes of memory per "
                            "pixel)")


def show_progress() -> None:
    """Log feature-extraction progress to stderr when it is a terminal (-v shows it anyway)."""
    if sys.stderr.isatty():
        logging.getLogger(PROGRESS_LOGGER).setLevel(logging.INFO)


def load_checked(load: Callable[[argparse.Namespace], object], args: argparse.Namespace):
    """``load(args)`` under the pixel limit, then the plausibility check of its scale."""
    from slam_predict.world.bitmap import pixel_limit
    from slam_predict.world.plausibility import check_scale

    with pixel_limit(args.max_pixels):
        world = load(args)
    check_scale(world, force=args.force)
    return world
