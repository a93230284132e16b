"""``slam-predict fidelity``: compare collected campaigns with the seed study's measured errors."""
from __future__ import annotations

import argparse

from slam_predict.cli.guards import (
    add_force_argument,
    check_at_least,
    check_out_file,
    check_share,
)
from slam_predict.metric.runs import MIN_COVERAGE

NAME = "fidelity"
HELP = ("compare campaigns' per-building errors with the seed study's table (Spearman rank "
        "correlation, median ratio ours/theirs)")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("campaigns", nargs="+", metavar="DATA",
                        help="campaign folders written by 'slam-predict collect'")
    parser.add_argument("--thesis", required=True, metavar="CSV",
                        help="the seed study's stats table, e.g. thesis/stats_realistic.csv")
    parser.add_argument("--min-runs", type=int, default=1,
                        help="skip buildings with fewer finished runs")
    parser.add_argument("--min-coverage", type=float, default=MIN_COVERAGE, metavar="SHARE",
                        help="leave out runs that explored less than this share of the "
                             "reachable free area: failed explorations (default "
                             f"{MIN_COVERAGE:g}, as the robot-aware learner; 0: every run)")
    parser.add_argument("--parts", metavar="YAML",
                        help="declared building parts (e.g. the buildings a setting was fitted "
                             "on and the rest): the collection chain's bars and run ends for "
                             "each part")
    parser.add_argument("--out", metavar="MD", help="also write the markdown tables to MD")
    parser.add_argument("--plot", metavar="PNG",
                        help="also write the ratios ours/theirs against free area to PNG")
    loo = parser.add_argument_group(
        "models against the seed study",
        "predict each building of a 'learn dataset' file leave-one-building-out, with the "
        "model kinds of a shipped plan-only model refitted on the other buildings, and score "
        "the predictions against the seed study's measured mean errors")
    source = loo.add_mutually_exclusive_group()
    source.add_argument("--loo-dataset", metavar="CSV",
                        help="dataset of the campaign (slam-predict learn dataset --errors "
                             "DATA/summary.csv ...), for a plan-only --loo-model")
    source.add_argument("--loo-runs", nargs="+", metavar="DATA",
                        help="campaign folders to refit a robot-aware --loo-model on (e.g. "
                             "those its card names); the robot scored is the one the compared "
                             "campaigns were collected with")
    loo.add_argument("--loo-model", default="own-realistic", metavar="MODEL",
                     help="model name (under the models folder) or folder whose card names "
                          "the model kind and learning configuration")
    loo.add_argument("--worlds", metavar="DIR",
                     help="with --loo-runs: folder of worlds to compute features on (the "
                          "card's feature configuration)")
    loo.add_argument("--jobs", type=int, default=1, metavar="N",
                     help="with --loo-runs: parallel workers (features and refits)")
    add_force_argument(parser)


def run(args: argparse.Namespace) -> int:
    from pathlib import Path

    from slam_predict.atomic import write_text
    from slam_predict.collect.fidelity import compare_campaign, markdown_report, read_thesis_table

    check_at_least(args.min_runs, 1, "--min-runs")
    check_share(args.min_coverage, "--min-coverage")
    check_at_least(args.jobs, 1, "--jobs")
    if args.loo_runs and not args.worlds:
        from slam_predict.errors import InputError

        raise InputError("--loo-runs needs --worlds DIR (the plans of the campaigns' buildings)")
    if args.out:
        check_out_file(args.out, args.force)
    thesis = read_thesis_table(Path(args.thesis))
    comparisons = [compare_campaign(Path(c), thesis, args.min_runs,
                                    min_coverage=args.min_coverage) for c in args.campaigns]
    text = markdown_report(comparisons, Path(args.thesis).name)
    if args.parts:
        text += parts_report(args.parts, comparisons, [Path(c) for c in args.campaigns])
    if args.loo_dataset:
        text += "\n" + models_against_thesis(args.loo_dataset, args.loo_model, thesis)
    if args.loo_runs:
        text += "\n" + robot_model_against_thesis(args, thesis)
    if args.out:
        write_text(args.out, text)
    if args.plot:
        from slam_predict.atomic import write_bytes
        from slam_predict.report.fidelity_plot import ratio_vs_area_png

        write_bytes(args.plot, ratio_vs_area_png(comparisons))
    print(text, end="")
    return 0


def parts_report(parts_file: str, comparisons, folders) -> str:
    """The markdown of each declared part's bars, over the buildings of all campaigns."""
    from slam_predict.collect.fidelity import Comparison
    from slam_predict.collect.fidelity_parts import load_parts, part_lines

    parts = load_parts(parts_file)
    pooled = Comparison(", ".join(c.name for c in comparisons),
                        [row for c in comparisons for row in c.rows],
                        {w: r for c in comparisons for w, r in c.per_run.items()})
    return "\n".join(["", f"### The chain's bars by part ({parts_file})",
                      *part_lines(pooled, parts, folders)]) + "\n"


def models_against_thesis(dataset_csv: str, model: str, thesis) -> str:
    """The markdown of :func:`slam_predict.learn.against.leave_one_out_against` for the
    components the seed study's table holds."""
    from slam_predict.learn import against
    from slam_predict.learn.dataset import read_dataset
    from slam_predict.learn.model import resolve_store
    from slam_predict.learn.store import default_models_dir

    card = resolve_store(default_models_dir(), model, None, None).card
    chosen = against.card_models(card, ["trans_mean", "rot_mean"])
    rows = against.leave_one_out_against(read_dataset(dataset_csv),
                                         against.card_learning_config(card), chosen, thesis,
                                         source=dataset_csv)
    return against.markdown(rows, card["name"], "the seed study")


def robot_model_against_thesis(args: argparse.Namespace, thesis) -> str:
    """The markdown of :func:`slam_predict.learn.robot.against.leave_one_building_out_against`:
    the robot-aware ``--loo-model`` refitted on ``--loo-runs`` without each building, predicting
    the compared campaigns' robot there, scored against the seed study."""
    from slam_predict.learn import against
    from slam_predict.learn.robot.against import leave_one_building_out_against as lobo
    from slam_predict.learn.robot.against import load_card_tables, robot_of_campaigns

    card, config, tables = load_card_tables(args.loo_model, args.loo_runs, args.worlds,
                                            args.jobs)
    config_id = robot_of_campaigns(args.campaigns, config, card)
    chosen = against.card_models(card, ["trans_mean", "rot_mean"])
    rows = lobo(tables, config, chosen, config_id, thesis, args.jobs)
    return against.markdown(rows, f"{card['name']} (robot {config_id})", "the seed study")
