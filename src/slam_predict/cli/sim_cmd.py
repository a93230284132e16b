"""``slam-predict sim``: use the simulator alone.

``slam-predict sim drive WORLD --path waypoints.yaml --out DIR`` drives the robot through the
waypoints (turn-then-go on the true pose) and writes DIR/run.log (CARMEN: ODOM every step,
ROBOTLASER1 every scan with the true laser pose and the odometry pose), ground_truth.tum,
odometry.tum and run.json (seed, configuration, the odometry error drawn, distance travelled).
"""
from __future__ import annotations

import argparse

from slam_predict.cli.guards import add_force_argument, check_out_dir, check_positive

NAME = "sim"
HELP = "run the Stage-equivalent simulator alone (scripted drives)"
ODOM_MODELS = ("uniform_per_run", "fixed", "none", "gaussian_per_step")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest="sim_command", metavar="ACTION")
    drive = sub.add_parser("drive", help="drive through waypoints, write a CARMEN log + TUM "
                                         "ground truth",
                           description="Drive the simulated robot through waypoints and write "
                                       "a CARMEN log, TUM ground truth and run metadata.")
    drive.add_argument("world", metavar="WORLD",
                       help="plan file: Stage .world, image (with --resolution), map YAML")
    drive.add_argument("--path", required=True, metavar="WAYPOINTS",
                       help="YAML file 'waypoints: [[x, y], ...]' (world frame, m)")
    drive.add_argument("--out", required=True, metavar="DIR", help="output folder")
    add_force_argument(drive)
    drive.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    drive.add_argument("--odom-model", choices=ODOM_MODELS,
                       help="odometry error model (default: the config's)")
    drive.add_argument("--config", metavar="YAML",
                       help="simulator config with a 'sim:' section (e.g. config/robot.yaml); "
                            "default: the world file's robot")
    drive.add_argument("--integrator", choices=("exact", "stage"), help="override the config's")
    drive.add_argument("--ranger-model", choices=("exact", "stage"),
                       help="laser: exact ranges or Stage 4.1.1's ray walk (override the config's)")
    drive.add_argument("--resolution", type=float, help="m/px, for image plans")
    drive.add_argument("--laser-message", choices=("ROBOTLASER1", "FLASER"),
                       default="ROBOTLASER1",
                       help="CARMEN laser line type (FLASER needs a 180-degree laser)")
    drive.add_argument("--max-time", type=float,
                       help="s of sim time before giving up (default 60 s + 4 s/m of path)")


def run(args: argparse.Namespace) -> int:
    if args.sim_command != "drive":
        from slam_predict.errors import InputError

        raise InputError("choose an action: slam-predict sim drive WORLD --path ... --out ...")
    return _drive(args)


def _config(args):
    import dataclasses

    from slam_predict.config import load_config
    from slam_predict.sim import SimConfig

    config = load_config(SimConfig, args.config, "sim") if args.config else SimConfig()
    if args.odom_model:
        config = dataclasses.replace(config, odom=dataclasses.replace(config.odom,
                                                                      model=args.odom_model))
    if args.integrator:
        config = dataclasses.replace(config, integrator=args.integrator)
    if args.ranger_model:
        config = dataclasses.replace(config, ranger_model=args.ranger_model)
    return config


def _drive(args: argparse.Namespace) -> int:
    import logging
    import math
    import os

    import numpy as np

    from slam_predict import __version__
    from slam_predict.config import config_hash, to_dict
    from slam_predict.errors import InputError
    from slam_predict.sim import Simulator
    from slam_predict.sim.drive import FollowerConfig, drive, read_waypoints, write_run
    from slam_predict.world.load import load_plan

    check_out_dir(args.out, args.force, inputs=(args.world, args.path, args.config))
    check_positive(args.max_time, "--max-time")
    world = load_plan(args.world, resolution=args.resolution)
    config = _config(args)
    waypoints = read_waypoints(args.path, world)
    try:
        sim = Simulator(world, config, np.random.default_rng(args.seed))
    except ValueError as exc:  # robot/laser values of the world file the config does not fix
        raise InputError(str(exc), args.world) from None
    if args.laser_message == "FLASER" and abs(sim.laser.fov - math.pi) > 1e-6:
        raise InputError(f"FLASER lines assume a 180-degree laser; this one covers "
                         f"{math.degrees(sim.laser.fov):g} degrees (use ROBOTLASER1)", args.world)
    follower = FollowerConfig(max_time=args.max_time)
    log = drive(sim, waypoints, follower, source=args.path)
    metadata = {
        "tool": f"slam_predict {__version__}", "command": "sim drive",
        "world": os.path.abspath(args.world), "world_name": world.name,
        "waypoints": waypoints.tolist(), "seed": args.seed,
        "start_pose": world.start_pose.tolist(),
        "sim_config": to_dict(config), "sim_config_hash": config_hash(config),
        "robot": to_dict(sim.robot), "laser": to_dict(sim.laser), "interval_sim": sim.dt,
        "odom_error": sim.odom_error, "follower": to_dict(follower),
        "steps": len(log.t), "scans": len(log.scans), "duration_s": log.t[-1] if log.t else 0.0,
        "distance_m": log.path_length(), "rotation_rad": log.rotation(),
        "stalled_steps": log.stalled_steps, "laser_message": args.laser_message,
    }
    write_run(args.out, log, sim, metadata, args.laser_message)
    logging.getLogger(__name__).info("wrote %s: %d scans, %.1f m in %.1f s", args.out,
                                     len(log.scans), metadata["distance_m"],
                                     metadata["duration_s"])
    return 0
