"""``slam-predict learn evaluate|train --runs``: robot-aware models from campaign run records.

``learn evaluate --runs DATA_DIR... (--worlds DIR | --features CSV) [--design YAML...] --out
EVAL_DIR`` and ``learn train --runs ... --name NAME [--evaluation-out EVAL_DIR]`` (older
spelling, deprecated: ``learn robots DATA_DIR... [--out EVAL_DIR] [--name NAME]``) read
every ``<world>/run_NNN/run.json``, build the RUN and POINT tables (the range capped at the
runs' GMapping maxUrange), join the plan features, evaluate the models (leave buildings out,
leave configurations out, both) and write ``EVAL_DIR/robots_eval.md`` + CSVs; with
``--name`` they fit the models on every run and
writes the model folder, whose robot inputs' training ranges are the design files' bounds with
``--design`` (checked against the runs). Dispatched from :mod:`learn_cmd`.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import shlex
import sys
from pathlib import Path

from slam_predict.cli.deprecated import add_renamed_option
from slam_predict.cli.guards import add_force_argument, check_at_least, check_out_dir
from slam_predict.errors import InputError

HELP = "robot-aware models: plan features + robot inputs from campaign runs"
HELP_OLD = HELP + " (deprecated: use 'learn evaluate|train --runs DATA_DIR...')"
DEPRECATED = ("slam-predict learn: warning: 'learn robots' is deprecated and goes in the next "
              "release; use 'learn evaluate --runs DATA_DIR... --out EVAL_DIR' or 'learn "
              "train --runs DATA_DIR... --name NAME [--evaluation-out EVAL_DIR]'")
# options of the folded spelling that only robot-aware learning reads (attribute → option)
ROBOT_ONLY = {"worlds": "--worlds", "features": "--features",
              "feature_version": "--feature-version", "design": "--design",
              "feature_config": "--feature-config", "folds": "--folds",
              "repeats": "--repeats", "seed": "--seed",
              "evaluation_from": "--evaluation-from"}
PLAN_ONLY = {"splits": "--splits", "no_loo": "--no-loo",
             "reference_features": "--reference-features"}


def _add_sources(group) -> None:
    """--worlds | --features (a mutually exclusive group of the old spelling)."""
    group.add_argument("--worlds", metavar="DIR", help="folder of worlds to compute features on")
    group.add_argument("--features", metavar="CSV", help="precomputed features (world, ...)")


def _add_learning_options(group) -> None:
    """The options every spelling of robot-aware learning reads besides the sources."""
    group.add_argument("--feature-version", help="feature version of a --features table")
    group.add_argument("--design", metavar="YAML", nargs="+",
                       help="the campaigns' design file(s) (e.g. data/campaigns/robots/"
                            "design.yaml): the card's robot input ranges become their bounds")
    group.add_argument("--feature-config", metavar="YAML",
                       help="with --worlds: feature configuration (section 'features')")
    group.add_argument("--folds", type=int, metavar="N", help="folds of each protocol")
    group.add_argument("--repeats", type=int, metavar="N",
                       help="evaluate on N shufflings of the groups; scores are their mean")
    group.add_argument("--seed", type=int, help="seed of folds, trees and the GP optimiser")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of the old spelling ``learn robots``."""
    parser.add_argument("data", nargs="+", metavar="DATA_DIR",
                        help="campaign folder(s) holding WORLD/run_NNN/run.json")
    _add_sources(parser.add_mutually_exclusive_group(required=True))
    _add_learning_options(parser)
    parser.add_argument("--out", metavar="EVAL_DIR",
                        help="evaluation folder (robots_eval.md, robots_eval.csv, tables)")
    parser.add_argument("--name", help="also train on every run and write models/NAME")
    parser.add_argument("--models-dir", metavar="DIR", help="where model folders go "
                                                            "(default models/)")
    parser.add_argument("--description", default="", help="one sentence for the card")
    parser.add_argument("--config", metavar="YAML",
                        help="robot learning configuration (default: "
                             "config/robot_learning.yaml)")
    kinds = parser.add_argument("--estimators", dest="models", nargs="+", metavar="KIND",
                                help="estimator kinds (elasticnet gradient_boosting "
                                     "trend_boosting gaussian_process)")
    add_renamed_option(parser, "--models", kinds)
    parser.add_argument("--jobs", type=int, default=1, help="worker processes (default 1)")
    add_force_argument(parser)


def add_robot_options(parser: argparse.ArgumentParser) -> None:
    """The robot-aware options of ``learn evaluate|train`` (``--runs`` selects that family;
    ``--config`` then names a robot learning configuration and ``--estimators`` its kinds)."""
    group = parser.add_argument_group(
        "robot-aware models (plan features + the robot's laser and odometry as inputs)")
    group.add_argument("--runs", nargs="+", metavar="DATA_DIR",
                       help="campaign folder(s) holding WORLD/run_NNN/run.json, instead of "
                            "DATASET (--config: default config/robot_learning.yaml)")
    _add_sources(group)
    _add_learning_options(group)


def _check_family(args: argparse.Namespace) -> None:
    """InputError for DATASET and --runs together (or neither) and for options of the other
    family."""
    if args.dataset and args.runs:
        raise InputError("give either DATASET or --runs DATA_DIR..., not both")
    if not args.dataset and not args.runs:
        raise InputError("give a DATASET (from 'learn dataset') or --runs DATA_DIR... "
                         "(robot-aware models)")
    wrong = PLAN_ONLY if args.runs else ROBOT_ONLY
    given = [option for key, option in wrong.items() if getattr(args, key, None)]
    if given:
        family = "plan-only models (DATASET)" if args.runs else "robot-aware models (--runs)"
        raise InputError(f"{given[0]} applies to {family} only")
    if args.runs and bool(args.worlds) == bool(args.features):
        raise InputError("with --runs give one of --worlds DIR or --features CSV")


def run_folded(args: argparse.Namespace, train: bool) -> bool:
    """Run ``learn evaluate|train --runs`` as the robot-aware learning; False (nothing done)
    for a DATASET, after checking that no robot-aware option was given with it."""
    _check_family(args)
    if not args.runs:
        return False
    run(argparse.Namespace(
        data=args.runs, worlds=args.worlds, features=args.features,
        feature_version=args.feature_version, design=args.design,
        feature_config=args.feature_config,
        out=args.evaluation_out if train else args.out, name=args.name if train else None,
        models_dir=args.models_dir if train else None,
        description=args.description if train else "", config=args.config,
        models=args.models, folds=args.folds, repeats=args.repeats, seed=args.seed,
        slam=args.slam,
        jobs=args.jobs, force=args.force,
        evaluation_from=getattr(args, "evaluation_from", None) if train else None))
    return True


def slam_option(args: argparse.Namespace) -> str:
    """The algorithm of ``--slam`` (its registry name; gmapping when not given)."""
    from slam_predict.learn.card import DEFAULT_SLAM, check_slam
    from slam_predict.slam import canonical_name

    name = getattr(args, "slam", None)
    if name is None:
        return DEFAULT_SLAM
    name = canonical_name(name)
    check_slam(name)
    return name


def default_config_path() -> Path:
    from slam_predict.learn.store import default_models_dir

    return default_models_dir().parent / "config" / "robot_learning.yaml"


def load_config(args: argparse.Namespace):
    """The configuration file (or the defaults) with the command line's changes."""
    from slam_predict.config import from_dict, to_dict
    from slam_predict.learn.robot.config import load_robot_learning_config

    path = args.config or (str(default_config_path()) if default_config_path().is_file()
                           else None)
    changes = to_dict(load_robot_learning_config(path))
    check_at_least(args.folds, 2, "--folds")
    check_at_least(args.seed, 0, "--seed")
    check_at_least(args.repeats, 1, "--repeats")
    for key in ("models", "folds", "repeats", "seed"):
        if getattr(args, key) is not None:
            changes[key] = getattr(args, key)
    from slam_predict.learn.robot.config import RobotLearningConfig

    return from_dict(RobotLearningConfig, changes, "command line")


def _check_outputs(args: argparse.Namespace) -> Path | None:
    """The model folder to write (None without --name), every output checked first."""
    from slam_predict.learn.store import default_models_dir

    check_at_least(args.jobs, 1, "--jobs")
    if getattr(args, "evaluation_from", None) and args.out:
        raise InputError("--evaluation-from reuses an evaluation: it writes no evaluation "
                         "folder (drop --evaluation-out)")
    if not args.out and not args.name:
        raise InputError("nothing to write: give --out EVAL_DIR and/or --name NAME")
    inputs = [*args.data, args.features, args.worlds, args.config, *(args.design or [])]
    if args.out:
        check_out_dir(args.out, args.force, inputs=inputs)
    if not args.name:
        return None
    if not args.name.strip() or os.sep in args.name:
        raise InputError(f"--name must be a folder name, got {args.name!r}")
    target = Path(args.models_dir or default_models_dir()) / args.name
    check_out_dir(target, args.force, "--name", inputs=inputs)
    return target


def _feature_config(path: str | None) -> dict:
    from slam_predict.learn.config import yaml_section

    return {} if path is None else yaml_section(path, "features")


def _failures(outcomes: dict | None) -> list[str]:
    """The header line on failed explorations (none when every run explored enough)."""
    failed = {c: e for c, e in ((outcomes or {}).get("by_config") or {}).items() if e["failed"]}
    if not failed:
        return []
    total = sum(e["runs"] for e in outcomes["by_config"].values())
    return [f"- failed explorations (coverage < {outcomes['min_coverage']:g}, not learned "
            f"from): {sum(e['failed'] for e in failed.values())} of {total} runs; "
            + ", ".join(f"{c} ({e['range_m']:.3g} m laser) {e['failed']}/{e['runs']}"
                        for c, e in sorted(failed.items(), key=lambda kv: kv[1]["range_m"]))]


def _header(data, tables, config, plan: list[str], outcomes: dict | None = None) -> list[str]:
    from slam_predict.learn.card import range_cap_name
    from slam_predict.words import plural

    skipped = ", ".join(f"{n} {reason}" for reason, n in sorted(data.skipped.items()))
    return [f"- runs: {len(data.runs)} used" + (f" (skipped: {skipped})" if skipped else ""),
            f"- points: {len(data.groups)} ({plural(len(data.worlds), 'building')} × "
            f"{plural(len(data.configs), 'configuration')} present)",
            f"- plan features ({data.feature_version}): {', '.join(plan)}; robot inputs: "
            f"laser_range_max_m (capped at {range_cap_name(data.slam)} "
            + (f"{data.max_urange_m:g} m" if data.max_urange_m is not None else "(unset)")
            + "), " + ", ".join(config.robot_inputs[1:])
            + ("; plan × robot: laser_blind_fraction (sight lines without a wall within the "
               "laser's range)" if config.sightline_input else ""),
            f"- models: {', '.join(config.models)}; {config.folds} folds per protocol"
            + (f" × {config.repeats} repeats (scores: mean ± sd)" if config.repeats > 1 else "")
            + "; "
            f"seed {config.seed}; intervals: CV+ grouped by building, "
            f"{config.conformal_folds} folds, {100 * config.confidence:g} %",
            f"- best per component: lowest median % error under '{config.select_protocol}'",
            *_failures(outcomes), *_ceilings(tables)]


def _ceilings(tables) -> list[str]:
    """The header line on the R² that run-to-run noise leaves reachable (means only)."""
    from slam_predict.learn.robot.evaluate import replicate_r2_ceiling
    from slam_predict.learn.robot.plain import MEANS
    from slam_predict.learn.tables import SYMBOLS

    parts = []
    for component in MEANS:
        ceiling, n = replicate_r2_ceiling(tables, component)
        if math.isfinite(ceiling):
            parts.append(f"{SYMBOLS[component]} {ceiling:.2f} ({n} points)")
    if not parts:
        return []
    return ["- R² ceiling from run-to-run noise (what exact true means would score against "
            "these measured point means): " + ", ".join(parts)]


def write_evaluation(out: str, data, tables, config, rows, summary, best,
                     feature_meta: dict, outcomes: dict | None = None) -> None:
    """The evaluation folder, atomically; its features.csv (+ .json sidecar with the feature
    configuration) is reusable as ``--features``."""
    from slam_predict.atomic import atomic_dir
    from slam_predict.learn.dataset import to_csv_text
    from slam_predict.learn.robot.evaluate import report_markdown
    from slam_predict.learn.robot.inputs import ALL_ROBOT_INPUTS, DERIVED_INPUTS
    from slam_predict.learn.robot.rundata import runs_csv
    from slam_predict.learn.sources import write_feature_table
    from slam_predict.learn.tables import csv_text

    features_only = [n for n in tables.names
                     if n not in ALL_ROBOT_INPUTS and n not in DERIVED_INPUTS]
    with atomic_dir(out) as tmp:
        (tmp / "robots_eval.md").write_text(
            report_markdown(summary, best,
                            _header(data, tables, config, features_only, outcomes),
                            config.confidence))
        (tmp / "robots_eval.csv").write_text(csv_text(summary))
        (tmp / "robots_predictions.csv").write_text(csv_text(rows))
        (tmp / "runs.csv").write_text(runs_csv(data))
        (tmp / "points.csv").write_text(to_csv_text(data.tables_points(tables)))
        write_feature_table(data.features, data.feature_version, tmp / "features.csv",
                               feature_meta)
        (tmp / "best.json").write_text(json.dumps({"best": best}, indent=2) + "\n")


def _designs(paths: list[str] | None):
    """The card's record of the design files: None, one portable path, or a list of them."""
    from slam_predict.paths import portable_path

    if not paths:
        return None
    return portable_path(paths[0]) if len(paths) == 1 else [portable_path(p) for p in paths]


def run(args: argparse.Namespace) -> int:
    from slam_predict.learn.robot.evaluate import best_models, evaluate, summarize
    from slam_predict.learn.robot.outcomes import exploration_outcomes
    from slam_predict.learn.robot.rundata import learning_data
    from slam_predict.paths import portable_path

    target = _check_outputs(args)
    config = load_config(args)
    if args.design:
        from slam_predict.errors import require_file

        for path in args.design:
            require_file(path, "design file")
    feature_config = _feature_config(args.feature_config)
    slam = slam_option(args)
    # every building with a run, also those whose runs all failed: the failure model needs them
    data, features, full_config = learning_data(
        args.data, config, slam, every_world=True, features_csv=args.features,
        worlds_dir=args.worlds, feature_config=feature_config,
        feature_version=args.feature_version, n_jobs=args.jobs)
    outcomes = exploration_outcomes(args.data, config.min_coverage, slam)
    bounds = None
    if args.design:
        from slam_predict.learn.robot.domain import design_ranges

        undesigned = {run.config for run in data.runs if not run.designed}
        bounds = design_ranges(args.design, data.max_urange_m, data.configs, undesigned,
                               config.resolution_input)
    tables = data.config_tables(config)
    previous = getattr(args, "evaluation_from", None)
    if previous:
        rows, summary = None, evaluation_of_card(previous, config, args.data)
    else:
        rows = evaluate(tables, config, n_jobs=args.jobs)
        summary = summarize(rows)
    best = best_models(summary, config)
    if target is not None:
        best = _train(args, target, data, config, summary, best, full_config, bounds,
                      outcomes, features)
    if args.out:
        write_evaluation(args.out, data, tables, config, rows, summary, best,
                         {"feature_config": full_config,
                          "features_from": portable_path(args.worlds or args.features)},
                         outcomes)
    print(f"{len(data.runs)} runs, {len(data.groups)} points, {len(data.worlds)} buildings, "
          f"{len(data.configs)} configurations; best: "
          + ", ".join(f"{c} {m}" for c, m in best.items()))
    if args.out:
        print(f"evaluation written to {args.out}")
    if target is not None:
        print(f"model written to {target}")
    return 0


def evaluation_of_card(path: str, config, data_dirs: list[str]) -> list[dict]:
    """The evaluation summary rows recorded in the model card ``path`` (a card.json or its
    folder); InputError unless it is a robot-aware card trained on the same campaign folders
    with the same configuration (the failure model's settings aside)."""
    from slam_predict.config import to_dict
    from slam_predict.learn.card import ROBOT_KIND, check_kind, read_card
    from slam_predict.learn.robot.evaluate import summary_from_card
    from slam_predict.paths import portable_path

    folder = Path(path).parent if Path(path).name == "card.json" else Path(path)
    card = read_card(folder)
    check_kind(card, ROBOT_KIND, folder / "card.json")
    ignored = ("failure_coverage", "failure_c")
    ours = {k: v for k, v in to_dict(config).items() if k not in ignored}
    theirs = {k: v for k, v in (card.get("robot_learning_config") or {}).items()
              if k not in ignored}
    if json.loads(json.dumps(ours)) != theirs:
        raise InputError("--evaluation-from: the card was trained with another robot "
                         "learning configuration", folder / "card.json")
    if (card.get("sources") or {}).get("data") != [portable_path(d) for d in data_dirs]:
        raise InputError("--evaluation-from: the card was trained on other campaign folders",
                         folder / "card.json")
    return summary_from_card(card)


def _train(args, target: Path, data, config, summary, best, full_config, bounds,
           outcomes, features) -> dict[str, str]:
    """Write the model folder; the best kinds it ships (monotone ones only). ``features``: the
    plan features of every building with a run (the failure model's inputs)."""
    from slam_predict.learn.card import read_card
    from slam_predict.learn.provenance import campaign_sources
    from slam_predict.learn.robot.failure import outcome_runs
    from slam_predict.learn.robot.train import train_robot_store
    from slam_predict.paths import portable_path

    sources = {**campaign_sources(args.data),
               "features_from": portable_path(args.worlds or args.features),
               "design": _designs(args.design),
               "command": shlex.join(["slam-predict", *sys.argv[1:]])}
    train_robot_store(data, config, summary, best, target,
                      {"name": args.name, "description": args.description,
                       "feature_config": full_config, "sources": sources,
                       "design_bounds": bounds, "exploration": outcomes,
                       "outcome_runs": outcome_runs(args.data, data.max_urange_m, data.slam),
                       "outcome_features": features},
                      args.jobs)
    card = read_card(target)
    return {c: e["best"] for c, e in card["components"].items()}
