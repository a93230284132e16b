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
import math
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
                            "matches (usually a unit mistake); continue a --simulate --out "
                            "folder with another --seed or settings, as collect --force; "
                            "overwrite existing output files")
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


def plan_used(world, args: argparse.Namespace) -> dict:
    """What ``predict`` took from the plan, for its output: the scale (m/px) and where it came
    from, the free area (m²) and the start pose (m, m, deg) and where it came from."""
    from slam_predict.paths import portable_path

    provenance = world.provenance
    if args.resolution is not None:
        scale_from = "--resolution"
    elif getattr(args, "world", None):
        scale_from = f"--world {args.world}"
    elif provenance.get("format") == "layout-xml":
        scale_from = f"the layout's <scale> ({provenance['unit_m']:g} m per drawing unit)"
    elif provenance.get("resolution_from"):
        scale_from = portable_path(provenance["resolution_from"])
    elif provenance.get("format") == "stage":
        scale_from = "the .world's floorplan size"
    else:
        scale_from = str(provenance.get("format") or "the plan")
    if args.start:
        start_from = "--start"
    elif provenance.get("start_given"):
        start_from = "the plan"
    else:
        start_from = "the free cell of largest clearance"
    x, y, yaw = (float(v) for v in world.start_pose)
    return {"scale_m_per_px": float(world.resolution), "scale_from": scale_from,
            "free_area_m2": round(world.free_area_m2, 1),
            "start": [round(x, 3), round(y, 3), round(math.degrees(yaw), 2)],
            "start_from": start_from}


def plan_line(plan: dict) -> str:
    """``plan_used`` as one line of text."""
    x, y, yaw = plan["start"]
    return (f"plan: {plan['scale_m_per_px']:.4g} m/px ({plan['scale_from']}), free area "
            f"{plan['free_area_m2']:,.0f} m², start ({x:.2f} m, {y:.2f} m, {yaw:.0f} deg; "
            f"{plan['start_from']})")
