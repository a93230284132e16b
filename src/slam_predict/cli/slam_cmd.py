"""``slam-predict slam run INPUT --type NAME --config YAML --seed N --out DIR``: a SLAM back-end
(GMapping by default) over a CARMEN log or a ROS bag.

Writes DIR/slam.tum, DIR/slam.log, DIR/map.{yaml,pgm,png} and DIR/stats.json (see
:mod:`slam_predict.slam.runner`). ``--type`` is a name of :func:`slam_predict.slam.available`
(default: the config's ``type:``, else gmapping). ``--config`` takes the back-end's parameter
YAML (for gmapping slam_gmapping's, e.g. config/gmapping.yaml or
../shared/baselines/gmapping_real_intel.yaml); without it the back-end's defaults are used.

A sensor log of a collected run (``RUN/sensors.bag`` or ``RUN/sensors.log.gz``, beside a
``run.json`` with ``sensor_logs``) is replayed with the run's recorded back-end, parameters and
its in-loop SLAM generator (from the run's seed), so DIR/slam.tum reproduces RUN/slam_scans.tum
exactly; ``--type``, ``--config`` or ``--seed`` replace them.

``slam-predict slam beside ROUTES --settings YAML --out DIR [--jobs K]``: the back-end of the
settings beside every route (collected run with a sensor log) of a campaign, measured like a
collected run (:mod:`slam_predict.collect.beside`); resumable, writes DIR/summary.csv.
"""
from __future__ import annotations

import argparse

from slam_predict.cli.guards import add_force_argument, check_out_dir

NAME = "slam"
HELP = "run SLAM (GMapping or another back-end) offline over a recorded log"


def _non_negative(text: str) -> int:
    value = int(text)
    if value < 0:
        raise argparse.ArgumentTypeError("must be >= 0")
    return value


def _positive(text: str) -> int:
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError("must be >= 1")
    return value


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from slam_predict import slam

    sub = parser.add_subparsers(dest="slam_command", metavar="ACTION", required=True)
    run = sub.add_parser("run", help="a SLAM back-end over a CARMEN log or a ROS bag",
                         description="Run a SLAM back-end (default GMapping) over a CARMEN log "
                                     "(ODOM/FLASER/ROBOTLASER1) or a ROS bag (LaserScan + tf or "
                                     "Odometry) as its ROS node would.")
    run.add_argument("input", metavar="INPUT", help="CARMEN log (.log, .log.gz) or ROS bag")
    run.add_argument("--slam", "--type", dest="type", metavar="NAME",
                     help=f"SLAM back-end: {', '.join(slam.available())} (slam_toolbox: karto; "
                          "default: the config's type:, a collected run's, else gmapping)")
    run.add_argument("--config", metavar="YAML",
                     help="the back-end's parameters (default: a collected run's recorded "
                          "ones, else the back-end's defaults)")
    run.add_argument("--seed", type=_non_negative,
                     help="random seed (default: a collected run's SLAM generator, else 0)")
    run.add_argument("--out", required=True, metavar="DIR",
                     help="output folder (an existing non-empty one only with --force)")
    add_force_argument(run)
    run.add_argument("--max-scans", type=_positive, metavar="K",
                     help="only the first K scans of the input")
    bag = run.add_argument_group("ROS bag input")
    bag.add_argument("--scan-topic", help="LaserScan topic (default: the bag's only one)")
    bag.add_argument("--odom-topic", help="nav_msgs/Odometry topic (default: tf odom -> base)")
    bag.add_argument("--base-frame", default="base_link", help="robot frame (default base_link)")
    bag.add_argument("--odom-frame", default="odom", help="odometry frame (default odom)")
    beside = sub.add_parser(
        "beside", help="a SLAM back-end beside the routes of a collected campaign",
        description="Replay every collected run of ROUTES that kept its sensor log through the "
                    "back-end of --settings (its own real-time scan gate or compute delay) and "
                    "measure the pose it publishes at every scan with the run's metric and "
                    "seed: two SLAM algorithms on the same routes. Resumable: runs already in "
                    "--out are kept.")
    beside.add_argument("routes", metavar="ROUTES",
                        help="campaign folder collected with sensor_logs: true")
    beside.add_argument("--settings", required=True, metavar="YAML",
                        help="collection settings naming the back-end (slam:) on the routes' own "
                             "chain (simulator, navigation, explorer, stop rule, metric)")
    beside.add_argument("--out", required=True, metavar="DIR",
                        help="campaign folder for the beside runs (created, or resumed)")
    beside.add_argument("--jobs", type=int, default=1, help="local worker processes")


def _backend_and_params(args: argparse.Namespace, recorded):
    """(back-end name, parameters) from --type/--config, else the recorded run's, else the
    defaults."""
    from slam_predict import slam
    from slam_predict.config import load_yaml

    if args.config:
        values = load_yaml(args.config) or {}
        name = args.type or slam.type_in(values)
        return name, slam.params_from_dict(name, values, args.config)
    if recorded is not None and args.type in (None, recorded.slam_type):
        return recorded.slam_type, recorded.params
    name = args.type or "gmapping"
    return name, slam.params_from_dict(name, None)


def run(args: argparse.Namespace) -> int:
    if args.slam_command == "beside":
        return _beside(args)
    return _run_log(args)


def _beside(args: argparse.Namespace) -> int:
    from pathlib import Path

    from slam_predict.cli.guards import check_at_least
    from slam_predict.collect.beside import beside_campaign
    from slam_predict.collect.settings import load_settings

    check_at_least(args.jobs, 1, "--jobs")
    settings = load_settings(args.settings)
    ran = beside_campaign(Path(args.routes), settings, Path(args.out), args.jobs, print)
    print(f"{settings.slam.type} beside {args.routes}: {ran} run(s) replayed -> "
          f"{Path(args.out) / 'summary.csv'}")
    return 0


def _run_log(args: argparse.Namespace) -> int:
    from slam_predict.slam import canonical_name
    from slam_predict.slam.runner import evaluate, read_input, recorded_run, write_run
    from slam_predict.slam.runner import run as run_slam

    check_out_dir(args.out, args.force, inputs=(args.input, args.config))
    if args.type is not None:
        args.type = canonical_name(args.type)
    recorded = recorded_run(args.input)
    slam_type, params = _backend_and_params(args, recorded)
    rng, seed, compute = None, 0 if args.seed is None else args.seed, None
    if args.seed is None and recorded is not None and slam_type == recorded.slam_type:
        rng, seed, compute = recorded.rng(), recorded.seed, recorded.compute
    data = read_input(args.input, args.max_scans, scan_topic=args.scan_topic,
                      odom_topic=args.odom_topic, base_frame=args.base_frame,
                      odom_frame=args.odom_frame)
    result = run_slam(data, slam_type, params, seed, rng=rng, compute=compute)
    if rng is not None:
        result.stats["rng"] = f"in-loop SLAM generator of the collected run (seed {seed})"
    config = args.config or (recorded.run_json if recorded is not None else None)
    out = write_run(args.out, result, data, params, seed, config)
    stats = result.stats
    resamples = f"{stats['resamples']} resamples, " if "resamples" in stats else ""
    line = (f"{slam_type}: {stats['scans_processed']}/{len(data)} scans processed, "
            f"{resamples}CPU {stats['cpu_s']:.1f} s -> {out}")
    errors = evaluate(result)
    if errors:
        line += (f"; error vs reference {errors['slam']['trans_mean_m']:.3f} m "
                 f"(odometry {errors['odometry']['trans_mean_m']:.3f} m)")
    print(line)
    return 0
