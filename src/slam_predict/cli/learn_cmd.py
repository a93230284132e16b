"""``slam-predict learn``: build the learning dataset, evaluate models, train a model folder.

* ``learn dataset --errors CSV (--worlds DIR | --features CSV) --setting S --out DATASET.csv``
  joins per-building error statistics (collection summary or thesis table) with features.
* ``learn evaluate DATASET --out DIR`` runs the repeated 80/20 splits (and leave-one-building-
  out) and writes tables, CSVs and figures.
* ``learn train DATASET --name NAME`` evaluates, fits the best models on every building and
  writes ``models/NAME`` with its card.
* ``learn evaluate|train --runs DATA_DIR... (--worlds DIR | --features CSV)``: the same verbs
  for robot-aware models from campaign run records (:mod:`slam_predict.cli.learn_robots_cmd`);
  ``learn robots`` is their older spelling, kept for one release with a warning on stderr.
"""
from __future__ import annotations

import argparse
import logging
import math
import os

from slam_predict.cli.deprecated import add_renamed_option
from slam_predict.cli.guards import (
    add_force_argument,
    check_at_least,
    check_out_dir,
    check_out_file,
)
from slam_predict.errors import InputError

NAME = "learn"
HELP = "build learning datasets, evaluate regression models, train shipped models"
LOG = logging.getLogger(__name__)


def _common(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--config", metavar="YAML",
                        help="learning configuration (default: config/learning.yaml)")
    parser.add_argument("--splits", type=int, metavar="N", help="number of random splits")
    parser.add_argument("--no-loo", action="store_true",
                        help="skip leave-one-building-out")
    kinds = parser.add_argument("--estimators", dest="models", nargs="+", metavar="KIND",
                                help="estimator kinds (single fregression elasticnet "
                                     "random_forest gradient_boosting)")
    add_renamed_option(parser, "--models", kinds)
    parser.add_argument("--slam", metavar="NAME",
                        help="SLAM algorithm to learn: only its rows (DATASET) or runs (--runs) "
                             "are used and the card records it (gmapping, the default, or "
                             "karto)")
    parser.add_argument("--jobs", type=int, default=1, help="worker processes (default 1)")
    add_force_argument(parser)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest="learn_command", metavar="ACTION")
    ds = sub.add_parser("dataset", help="join error statistics with feature vectors")
    ds.add_argument("--errors", required=True, metavar="CSV",
                    help="summary.csv of a collection or a thesis stats_*.csv")
    src = ds.add_mutually_exclusive_group(required=True)
    src.add_argument("--worlds", metavar="DIR", help="folder of worlds to compute features on")
    src.add_argument("--features", metavar="CSV", help="precomputed features (world, ...)")
    setting = ds.add_argument("--thesis-setting", dest="setting",
                              help="the seed study's robot setting of the errors (realistic, "
                                   "optimistic...)")
    add_renamed_option(ds, "--setting", setting)
    ds.add_argument("--slam", metavar="NAME",
                    help="keep only the rows of this SLAM algorithm (gmapping or karto; a "
                         "summary.csv's rows take theirs from the run records beside it; "
                         "default: every row)")
    ds.add_argument("--min-runs", type=int, default=1,
                    help="skip buildings with fewer finished runs (a summary.csv's 'runs' "
                         "column; default: 1)")
    ds.add_argument("--slam-config-hash", help="SLAM configuration hash (default: the table's)")
    ds.add_argument("--feature-version", help="feature version of a --features table")
    ds.add_argument("--feature-config", metavar="YAML",
                    help="feature configuration (section 'features'; default: the defaults)")
    ds.add_argument("--save-features", metavar="CSV",
                    help="with --worlds: also write the feature table (reusable by --features)")
    ds.add_argument("--out", required=True, metavar="CSV", help="dataset file to write")
    ds.add_argument("--jobs", type=int, default=1, help="worker processes (default 1)")
    add_force_argument(ds)
    from slam_predict.cli import learn_robots_cmd

    ev = sub.add_parser("evaluate", help="repeated splits + leave-one-out → tables and plots")
    ev.add_argument("dataset", metavar="DATASET", nargs="?",
                    help="dataset CSV from 'learn dataset' (or --runs: robot-aware models)")
    ev.add_argument("--out", required=True, metavar="DIR", help="output folder")
    ev.add_argument("--title", default="Evaluation", help="title of tables.md")
    ev.add_argument("--reference-features", nargs="+", metavar="COLUMN",
                    help="use the dataset's ref_* columns as the only features (development)")
    _common(ev)
    learn_robots_cmd.add_robot_options(ev)
    tr = sub.add_parser("train", help="evaluate, fit the best models and write models/NAME")
    tr.add_argument("dataset", metavar="DATASET", nargs="?",
                    help="dataset CSV from 'learn dataset' (or --runs: robot-aware models)")
    tr.add_argument("--name", required=True, help="model folder name")
    tr.add_argument("--models-dir", metavar="DIR", help="where model folders go (default models/)")
    tr.add_argument("--description", default="", help="one sentence for the card")
    tr.add_argument("--priority", type=int, default=0,
                    help="rank among models of the same setting for '--model best'")
    tr.add_argument("--evaluation-out", metavar="DIR", help="also write the evaluation here")
    _common(tr)
    learn_robots_cmd.add_robot_options(tr)
    tr.add_argument("--evaluation-from", metavar="CARD",
                    help="with --runs: take the evaluation figures from this model card "
                         "(trained on the same runs and configuration) instead of evaluating "
                         "again; only the fitting, checks and failure model run")
    rb = sub.add_parser("robots", help=learn_robots_cmd.HELP_OLD,
                        description=learn_robots_cmd.HELP_OLD)
    learn_robots_cmd.add_arguments(rb)


def default_config_path() -> str:
    from slam_predict.learn.store import default_models_dir

    return str(default_models_dir().parent / "config" / "learning.yaml")


def load_learning_config(args: argparse.Namespace):
    from slam_predict.config import from_dict, to_dict
    from slam_predict.learn.config import LearningConfig, load_section

    path = args.config or default_config_path()
    config = (load_section(LearningConfig, path, "learning")
              if (args.config or os.path.isfile(path)) else LearningConfig())
    changes = to_dict(config)
    if args.splits is not None:
        if args.splits < 1:
            raise InputError(f"--splits must be ≥ 1, got {args.splits}")
        changes["evaluation"]["n_splits"] = args.splits
    if args.no_loo:
        changes["evaluation"]["leave_one_out"] = False
    if args.models:
        changes["models"] = list(args.models)
    return from_dict(LearningConfig, changes, "command line")


def _feature_config(path):
    from slam_predict.learn.config import yaml_section

    if path is None:
        return {}
    return yaml_section(path, "features")


def with_min_runs(errors: list, min_runs: int, path: str) -> list:
    """The rows with at least ``min_runs`` finished runs (a summary.csv's ``runs``); logs the
    buildings it skips. InputError for a table without runs, or when no building is left."""
    if min_runs <= 1:
        return errors
    if any(math.isnan(row.runs) for row in errors):
        raise InputError(f"--min-runs {min_runs}: the table has no runs column", path)
    kept = [row for row in errors if row.runs >= min_runs]
    skipped = sorted(row.world for row in errors if row.runs < min_runs)
    if skipped:
        LOG.info("%d buildings with fewer than %d runs skipped: %s", len(skipped), min_runs,
                 ", ".join(skipped))
    if not kept:
        raise InputError(f"no building has {min_runs} or more runs", path)
    return kept


def run_dataset(args: argparse.Namespace) -> int:
    from slam_predict.learn import dataset as ds
    from slam_predict.learn import sources

    check_at_least(args.jobs, 1, "--jobs")
    check_at_least(args.min_runs, 1, "--min-runs")
    check_out_file(args.out, args.force)
    check_out_file(ds.meta_path(args.out), args.force, "the JSON beside --out")
    if args.save_features:
        check_out_file(args.save_features, args.force, "--save-features")
    errors = with_min_runs(sources.read_error_table(args.errors, args.setting or ""),
                           args.min_runs, args.errors)
    if args.slam_config_hash:
        for row in errors:
            row.slam_config_hash = args.slam_config_hash
    if any(not row.setting for row in errors):
        raise InputError("the table has no setting column: give --thesis-setting", args.errors)
    if args.worlds:
        from slam_predict.features.plan import full_feature_config
        from slam_predict.learn.featurize import features_from_worlds

        feature_config = full_feature_config(_feature_config(args.feature_config))
        features, version = features_from_worlds(args.worlds, [r.world for r in errors],
                                                 feature_config, args.jobs)
        if args.save_features:
            sources.write_feature_table(features, version, args.save_features,
                                   {"feature_config": feature_config,
                                    "worlds": os.path.abspath(args.worlds)})
    else:
        feature_config = ds.read_meta(args.features).get("feature_config") or {}
        features = sources.read_feature_table(args.features)
        version = args.feature_version or ""
        if not version and not all("feature_version" in v for v in features.values()):
            raise InputError("features table has no feature_version column: give "
                             "--feature-version", args.features)
    data = ds.join(errors, features, version)
    if args.slam:
        from slam_predict.cli.learn_robots_cmd import slam_option

        data = data.select_slam(slam_option(args))
    meta = {"errors": os.path.abspath(args.errors), "setting": args.setting,
            "features_from": os.path.abspath(args.worlds or args.features),
            "feature_config": feature_config}
    ds.write_dataset(data, args.out, meta)
    print(f"{args.out}: {len(data)} buildings × {len(data.feature_names)} features "
          f"(setting {', '.join(sorted(set(data.setting)))}, feature version "
          f"{', '.join(sorted(set(data.feature_version)))})")
    return 0


def _read(path: str, slam: str, reference=None):
    """The dataset's rows of SLAM algorithm ``slam`` (ref_* columns as features when
    ``reference`` names them)."""
    from slam_predict.learn import dataset as ds

    data = ds.read_dataset(path).select_slam(slam)
    if reference:
        data = ds.reference_as_features(data, reference)
    return data


def run_evaluate(args: argparse.Namespace) -> int:
    from slam_predict.cli.learn_robots_cmd import run_folded, slam_option
    from slam_predict.learn.results import run_evaluation, write_evaluation
    from slam_predict.learn.tables import best_table

    if run_folded(args, train=False):
        return 0

    check_at_least(args.jobs, 1, "--jobs")
    check_out_dir(args.out, args.force, inputs=(args.dataset, args.config))
    config = load_learning_config(args)
    data = _read(args.dataset, slam_option(args), args.reference_features)
    outcome = run_evaluation(data, config, n_jobs=args.jobs)
    write_evaluation(data, config, outcome, args.out, args.title)
    print(best_table(outcome.summary), end="")
    print(f"written to {args.out}")
    return 0


def run_train(args: argparse.Namespace) -> int:
    from slam_predict.cli.learn_robots_cmd import run_folded, slam_option
    from slam_predict.learn.dataset import read_meta
    from slam_predict.learn.provenance import campaign_folder, campaign_sources
    from slam_predict.learn.results import run_evaluation, write_evaluation
    from slam_predict.learn.store import default_models_dir
    from slam_predict.learn.train import check_trainable, train_store

    if run_folded(args, train=True):
        return 0

    check_at_least(args.jobs, 1, "--jobs")
    check_out_dir(os.path.join(args.models_dir or default_models_dir(), args.name), args.force,
                  "--name", inputs=(args.dataset, args.config))
    if args.evaluation_out:
        check_out_dir(args.evaluation_out, args.force, "--evaluation-out",
                      inputs=(args.dataset, args.config))
    config = load_learning_config(args)
    data = _read(args.dataset, slam_option(args))
    check_trainable(data)
    outcome = run_evaluation(data, config, n_jobs=args.jobs)
    if args.evaluation_out:
        write_evaluation(data, config, outcome, args.evaluation_out, f"Model {args.name}")
    meta = read_meta(args.dataset)
    sources = {"dataset": os.path.basename(args.dataset),
               **{k: os.path.basename(str(v)) for k, v in meta.items()
                  if k in ("errors", "features_from") and v}}
    campaign = campaign_folder(meta["errors"]) if meta.get("errors") else None
    if campaign is not None:
        sources.update(campaign_sources([campaign]))
    out = train_store(data, config, outcome, args.name, args.models_dir or default_models_dir(),
                      args.description, args.priority, meta.get("feature_config") or {},
                      sources)
    print(f"model written to {out}")
    return 0


def run_robots(args: argparse.Namespace) -> int:
    """The old spelling of ``learn evaluate|train --runs``: kept for one release."""
    import sys

    from slam_predict.cli.learn_robots_cmd import DEPRECATED
    from slam_predict.cli.learn_robots_cmd import run as run_learn_robots

    print(DEPRECATED, file=sys.stderr)
    return run_learn_robots(args)


def run(args: argparse.Namespace) -> int:
    actions = {"dataset": run_dataset, "evaluate": run_evaluate, "train": run_train,
               "robots": run_robots}
    if args.learn_command not in actions:
        raise InputError("choose an action: dataset, evaluate, train or robots")
    return actions[args.learn_command](args)
