"""``slam-predict collect``: resumable batches of simulated explorations with GMapping.

Every input is checked before any run starts (worlds parsed, settings loaded strictly, --out
usable, counts ≥ 1): a bad one is one error line, exit 2, nothing written. The campaign folder's
campaign.json (:mod:`slam_predict.collect.campaign`) must agree with --seed and --settings.
SIGINT/SIGTERM stop the batch within one control step: finished runs are kept, the runs in
progress discarded, summary.csv written; exit 130/143.
"""
from __future__ import annotations

import argparse
import os
import signal
import sys
from pathlib import Path

from slam_predict.cli.guards import check_at_least, check_creatable
from slam_predict.errors import InputError

NAME = "collect"
HELP = "run (or resume) simulated explorations of worlds and write run records + summary.csv"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("worlds", nargs="+", metavar="WORLD",
                        help="Stage .world files, or folders of them")
    parser.add_argument("--out", required=True, metavar="DATA",
                        help="campaign folder (new, empty, or a campaign to resume)")
    parser.add_argument("--runs", default=None, metavar="N|auto",
                        help="runs per world, or 'auto' (pilot of 10, then |R| = z²s²/d²); "
                             "default 5, or with --design all of the design's runs")
    parser.add_argument("--max-runs", type=int, default=50, help="cap for --runs auto")
    parser.add_argument("--jobs", type=int, default=1, help="local worker processes")
    parser.add_argument("--scheduler", metavar="tcp://HOST:8786",
                        help="run on a Dask distributed cluster instead of local processes")
    parser.add_argument("--seed", type=int, default=0, help="base seed of the campaign")
    parser.add_argument("--settings", metavar="YAML",
                        help="collection settings (robot, gmapping, navigation, exploration, "
                             "stopping); default config/collect.yaml")
    parser.add_argument("--slam", metavar="NAME",
                        help="SLAM back-end: gmapping or karto (slam_toolbox: the same); without "
                             "--settings its shipped settings (config/collect.yaml, "
                             "config/collect_karto.yaml), with --settings their slam.type must "
                             "be it")
    parser.add_argument("--robot", metavar="YAML|NAME",
                        help="robot description file (laser, odometry error, footprint, speed "
                             "limits; e.g. config/robots/lds_360_3p5.yaml, or the name of a "
                             "shipped one: lds_360_3p5) applied over the settings")
    parser.add_argument("--design", metavar="YAML",
                        help="robot-configuration design (slam-predict design): each run uses "
                             "the robot of its building's design point; excludes --robot")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument("--force", action="store_true",
                        help="go on where a check would refuse: resume a campaign with another "
                             "--seed or other settings than its campaign.json records (the "
                             "change is kept in its history); use a robot file or --design "
                             "configurations that no real robot matches (usually a unit "
                             "mistake)")


def find_worlds(items: list[str]) -> dict[str, str]:
    """World name (file stem) → path, for .world files and folders of them."""
    worlds: dict[str, str] = {}
    for item in items:
        path = Path(item)
        if path.is_dir():
            files = sorted(path.glob("*.world"))
            if not files:
                raise InputError("folder holds no .world file", item)
        elif path.is_file():
            if path.suffix != ".world":
                raise InputError("not a Stage .world file", item)
            files = [path]
        else:
            raise InputError("world file not found", item)
        for file in files:
            if file.stem in worlds and worlds[file.stem] != str(file):
                raise InputError(f"two worlds named '{file.stem}'", file)
            worlds[file.stem] = str(file)
    return worlds


def parse_runs(text: str, option: str = "--runs"):
    """'auto' or a positive run count (``option`` names it in the error)."""
    if text == "auto":
        return text
    if not text.isdigit() or int(text) < 1:
        raise InputError(f"{option} must be a positive integer or 'auto', got '{text}'")
    return int(text)


def load_worlds(worlds: dict[str, str], footprint_side: float | None = None) -> None:
    """Parse every world of the batch once, before any run starts (one error line each);
    ``footprint_side`` (m) is the simulator's footprint when the settings override the
    World's."""
    from slam_predict.world.load import load_plan

    for path in worlds.values():
        try:
            world = load_plan(path)
        except InputError:
            raise
        except (OSError, ValueError) as exc:
            raise InputError(f"cannot load the world: {exc}", path) from None
        check_start_footprint(world, path, footprint_side)


def check_start_footprint(world, path: str, footprint_side: float | None = None) -> None:
    """InputError when the robot's footprint (``footprint_side`` m, else the World's) at the
    world's start pose overlaps an obstacle: Stage would stall every move of such a run."""
    from slam_predict.sim.raycast import LaserGrid

    x, y, yaw = world.start_pose
    side = world.robot.footprint_side if footprint_side is None else footprint_side
    if LaserGrid.of_world(world).collides(x, y, yaw, side):
        raise InputError(f"the robot's footprint at the start pose ({x:.2f}, {y:.2f}) overlaps "
                         "an obstacle, so every move would stall (move robot_pose)", path)


def load_run_design(args: argparse.Namespace, worlds: dict[str, str]):
    """The robot design of ``--design``, or None; InputError when it is combined with --robot,
    a world is not in it, or (unless --force) a configuration has a laser no robot has."""
    if not args.design:
        return None
    from slam_predict.collect.robot_design import check_plausible, load_design

    if args.robot:
        raise InputError("--design gives every run its robot; it excludes --robot")
    design = load_design(args.design)
    for name, path in worlds.items():
        if name not in design.worlds:
            raise InputError(f"world '{name}' is not in the design {args.design}", path)
    check_plausible(design, args.force, args.design)
    return design


def design_runs(text: str | None, design) -> int:
    """Runs per world of a design campaign: all of the design's, or ``--runs`` N ≤ that."""
    if text is None:
        return design.runs_per_world
    runs = parse_runs(text)
    if runs == "auto" or runs > design.runs_per_world:
        raise InputError(f"with --design, --runs must be 1..{design.runs_per_world} (the "
                         f"design's runs per world), got '{text}'")
    return runs


def run(args: argparse.Namespace) -> int:
    from slam_predict.collect.batch import Batch, BatchConfig
    from slam_predict.collect.campaign import (
        check_out_folder,
        file_sha256,
        identity,
        open_campaign,
    )
    from slam_predict.collect.record import code_version
    from slam_predict.collect.settings import load_settings, settings_for_slam
    from slam_predict.collect.summary import write_summary
    from slam_predict.paths import portable_path
    from slam_predict.words import plural

    check_at_least(args.jobs, 1, "--jobs")
    check_at_least(args.max_runs, 1, "--max-runs")
    args.settings = settings_for_slam(args.slam, args.settings)
    worlds = find_worlds(args.worlds)
    settings = load_settings(args.settings, robot=args.robot, force_robot=args.force)
    design = load_run_design(args, worlds)
    runs = design_runs(args.runs, design) if design else parse_runs(args.runs or "5")
    out = Path(args.out)
    check_out_folder(out)
    check_creatable(out)
    footprint = design.base.footprint_side if design else settings.sim.robot.footprint_side
    load_worlds(worlds, footprint)
    current = identity(settings, args.seed, code_version())
    options = {"settings": args.settings} if args.settings else {}
    if args.robot:
        options.update(robot=args.robot, force_robot=args.force)
    if design:
        options["design"] = os.path.abspath(args.design)   # the workers may run elsewhere
        current["design"] = {"file": portable_path(args.design),
                             "sha256": file_sha256(args.design)}
    open_campaign(out, current, force=args.force,
                  run_hashes=design.run_hashes(settings, args.design) if design else None)
    config = BatchConfig(runs=runs, max_runs=args.max_runs, jobs=args.jobs,
                         scheduler=args.scheduler, base_seed=args.seed,
                         progress=not args.no_progress, options=options)
    if design:
        config.episode = "slam_predict.collect.episode:run_design_episode"
    batch = Batch(worlds, out, config)
    done = batch.run()
    summary = write_summary(out)
    print(f"{plural(done, 'run')} done; summary: {summary}")
    for failure in batch.failures:
        print(f"failed: {failure}")
    if batch.stopped_by is not None:
        name = signal.Signals(batch.stopped_by).name
        print(f"slam-predict collect: stopped by {name}; the runs in progress were discarded",
              file=sys.stderr)
        return 128 + batch.stopped_by
    return 1 if batch.failures else 0
