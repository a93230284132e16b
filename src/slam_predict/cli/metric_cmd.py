"""``slam-predict metric``: Kümmerle relation error of recorded trajectories, relations, log repair.

  slam-predict metric evaluate --slam SLAM --gt GT [--format auto|tum|carmen|bag]
                               [--pairs auto|all|consecutive|N]
  slam-predict metric evaluate --slam SLAM --relations REF.relations
  slam-predict metric relations --gt GT --pairs N --out REF.relations
  slam-predict metric adjust LOG [--out FILE]

Association: the reference's consecutive repeated poses are removed (thesis), then every estimated
stamp is matched one-to-one to the nearest reference stamp within --t-max-diff (see
slam_predict.metric.association). Against a relations file, each relation stamp takes the
nearest estimated pose within --t-max-diff (default 0.1 s there, as metricEvaluator).
"""
from __future__ import annotations

import argparse
import os

from slam_predict.cli.guards import add_force_argument, check_at_least, check_out_file, plural
from slam_predict.errors import InputError

NAME = "metric"
HELP = "Kümmerle relation error of SLAM trajectories (TUM, CARMEN, ROS bag)"

FORMATS = ("auto", "tum", "carmen", "bag")
CARMEN_SUFFIXES = (".log", ".log.gz", ".clf", ".carmen", ".gz")
TUM_SUFFIXES = (".tum", ".txt", ".csv")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest="metric_command", metavar="ACTION")
    ev = sub.add_parser("evaluate",
                        help="relation error of a SLAM trajectory against ground truth")
    _add_input_args(ev, "slam", "estimated trajectory (TUM, CARMEN log or ROS bag)", required=True)
    _add_input_args(ev, "gt", "ground-truth trajectory (TUM, CARMEN log or ROS bag)",
                    required=False)
    ev.add_argument("--relations", metavar="FILE",
                    help="reference relations file (Freiburg format) instead of --gt")
    ev.add_argument("--format", choices=FORMATS, default="auto",
                    help="input format of both files (default: from the file name)")
    _add_pair_args(ev)
    ev.add_argument("--t-max-diff", type=float, default=None, metavar="S",
                    help="max timestamp difference for matching, s (default 0.01; 0.1 with "
                         "--relations)")
    ev.add_argument("--no-dedupe", action="store_true",
                    help="keep consecutive repeated reference poses (default: removed)")
    ev.add_argument("--ddof", type=int, default=1, choices=(0, 1),
                    help="std of per-relation errors: 1 = sample std (default), 0 = population")
    ev.add_argument("--json", action="store_true", help="print the result as JSON")
    ev.add_argument("--out", metavar="FILE", help="also write the JSON result to FILE")
    add_force_argument(ev)
    ev.set_defaults(_action=_evaluate)

    rel = sub.add_parser("relations", help="sample random forward relations from a ground truth")
    _add_input_args(rel, "gt", "ground-truth trajectory", required=True)
    rel.add_argument("--format", choices=FORMATS, default="auto")
    rel.add_argument("--pairs", type=int, default=500, help="number of relations (default 500)")
    rel.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    rel.add_argument("--no-dedupe", action="store_true")
    rel.add_argument("--out", required=True, metavar="FILE", help="relations file to write")
    add_force_argument(rel)
    rel.set_defaults(_action=_relations)

    adj = sub.add_parser("adjust", help="drop a truncated last line of a CARMEN/TUM log (thesis)")
    adj.add_argument("log", help="CARMEN or TUM file")
    adj.add_argument("--out", metavar="FILE", help="write here instead of rewriting LOG")
    adj.add_argument("--kind", choices=("auto", "carmen", "tum"), default="auto")
    add_force_argument(adj, "overwrite an existing --out FILE (default: refuse)")
    adj.set_defaults(_action=_adjust)


def _add_input_args(parser, name: str, help_text: str, required: bool) -> None:
    parser.add_argument(f"--{name}", required=required, metavar="FILE", help=help_text)
    parser.add_argument(f"--{name}-topic", metavar="TOPIC",
                        help=f"bag topic of the {name} poses (PoseStamped, Odometry, ... or "
                             "/tf:parent.child)")
    parser.add_argument(f"--{name}-field", choices=("pose", "odom"), default="pose",
                        help="CARMEN: laser pose fields (default) or odometry fields")


def _add_pair_args(parser) -> None:
    parser.add_argument("--pairs", default="auto",
                        help="auto (thesis: pilot of 500, then the 99%% sample size for "
                             "±0.02 m / ±0.002 rad), all (every forward pair), consecutive "
                             "(i, i+delta), or a number N of random forward pairs")
    parser.add_argument("--delta", type=int, default=1, help="frame step for 'consecutive'")
    parser.add_argument("--seed", type=int, nargs="+", default=[0],
                        help="seed of the pair sampling: one integer, or several (a run "
                             "record's metric.info.seed, to reproduce its numbers)")


def run(args) -> int:
    action = getattr(args, "_action", None)
    if action is None:
        raise InputError("choose an action: evaluate, relations or adjust")
    return action(args)


# ----------------------------------------------------------------------------------- inputs

def detect_format(path: str, fmt: str) -> str:
    """The input format of ``path``: ``fmt`` unless 'auto', else from the name."""
    if fmt != "auto":
        return fmt
    lower = path.lower()
    if lower.endswith(".bag") or os.path.isfile(os.path.join(path, "metadata.yaml")):
        return "bag"
    if lower.endswith(TUM_SUFFIXES):
        return "tum"
    if lower.endswith(CARMEN_SUFFIXES):
        return "carmen"
    raise InputError("cannot tell the trajectory format from the name; use --format", path)


def load_trajectory(path: str, fmt: str, topic: str = None, field: str = "pose"):
    """A :class:`~slam_predict.metric.evaluate.StampedPoses` from a TUM, CARMEN or bag file."""
    from slam_predict.errors import require_file
    from slam_predict.metric.evaluate import StampedPoses

    fmt = detect_format(path, fmt)
    if fmt == "bag":
        from slam_predict.formats.rosbag import read_pose_topic

        if not topic:
            raise InputError("bag input needs the pose topic (--slam-topic / --gt-topic)", path)
        return StampedPoses(*read_pose_topic(path, topic))
    require_file(path, "trajectory")
    if fmt == "tum":
        from slam_predict.formats.tum import read_tum

        return StampedPoses(*read_tum(path))
    from slam_predict.formats.carmen import read_log

    log = read_log(path)
    if log.scans:
        poses = log.scan_poses if field == "pose" else log.scan_odom_poses
        return StampedPoses(log.scan_times, poses)
    if len(log.odometry):
        return StampedPoses(log.odometry.t, log.odometry.poses)
    raise InputError("CARMEN log holds no FLASER/ROBOTLASER1/ODOM poses", path)


def parse_pairs(text: str):
    """'auto' | 'all' | 'consecutive' → PairSelection; a positive integer → int."""
    from slam_predict.metric.relations import PairSelection

    if text in ("auto", "all", "consecutive"):
        return PairSelection(text)
    try:
        value = int(text)
    except ValueError:
        raise InputError(f"--pairs must be auto, all, consecutive or a number, got {text!r}") \
            from None
    if value < 1:
        raise InputError(f"--pairs must be at least 1, got {value}")
    return value


# ---------------------------------------------------------------------------------- actions

def _evaluate(args) -> int:
    import numpy as np

    from slam_predict.formats.relations import read_relations
    from slam_predict.metric import evaluate as ev

    if not args.gt and not args.relations:
        raise InputError("give the reference: --gt FILE or --relations FILE")
    if args.gt and args.relations:
        raise InputError("give either --gt or --relations, not both")
    check_at_least(args.t_max_diff, 0, "--t-max-diff")
    check_at_least(args.delta, 1, "--delta")
    pairs = parse_pairs(args.pairs)
    if args.out:
        check_out_file(args.out, args.force)
    est = load_trajectory(args.slam, args.format, args.slam_topic, args.slam_field)
    if args.relations:
        relations = read_relations(args.relations)
        tol = ev.RELATIONS_TOL if args.t_max_diff is None else args.t_max_diff
        result = ev.evaluate_relations(est, relations, tol, args.ddof, source=args.slam)
    else:
        ref = load_trajectory(args.gt, args.format, args.gt_topic, args.gt_field)
        tol = ev.DEFAULT_TOL if args.t_max_diff is None else args.t_max_diff
        result = ev.evaluate_trajectories(
            est, ref, pairs=pairs, rng=np.random.default_rng(sampling_seed(args.seed)),
            delta=args.delta,
            tol=tol, dedupe=not args.no_dedupe, ddof=args.ddof, source=args.slam)
        result.info["seed"] = sampling_seed(args.seed)
    result.info.update({"slam": args.slam, "reference": args.gt or args.relations})
    if args.out:
        from slam_predict.atomic import write_text

        write_text(args.out, result.to_json() + "\n")
    print(result.to_json() if args.json else result.table())
    return 0


def sampling_seed(values):
    """One int for a single --seed value, else the list (numpy seeds both ways alike)."""
    return int(values[0]) if len(values) == 1 else [int(v) for v in values]


def _relations(args) -> int:
    import numpy as np

    from slam_predict.formats.relations import write_relations
    from slam_predict.metric.evaluate import sample_relations

    if args.pairs < 1:
        raise InputError(f"--pairs must be at least 1, got {args.pairs}")
    check_out_file(args.out, args.force)
    ref = load_trajectory(args.gt, args.format, args.gt_topic, args.gt_field)
    if len(ref.t) < 2:
        raise InputError("need at least 2 poses to sample relations", args.gt)
    relations = sample_relations(ref, args.pairs, np.random.default_rng(args.seed),
                                 dedupe=not args.no_dedupe)
    header = f"{args.pairs} random forward relations of {args.gt}, seed {args.seed}"
    write_relations(args.out, relations, header=[header])
    print(f"wrote {plural(len(relations), 'relation')} to {args.out}")
    return 0


def _adjust(args) -> int:
    from slam_predict.metric.association import drop_truncated_last_line

    if args.out:
        check_out_file(args.out, args.force)
    removed = drop_truncated_last_line(args.log, args.out, args.kind)
    target = args.out or args.log
    print(f"{target}: {'dropped a truncated last line' if removed else 'no truncated last line'}")
    return 0
