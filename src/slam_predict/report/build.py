"""Assemble the campaign report: one self-contained HTML page, written atomically.

Page: campaign overview, per-building summary, one section per world (map with trajectories,
per-run table), and — when model folders are given — the learning section: each model card
with its scores, and its predictions for the campaign's worlds next to the measured values
(a robot-aware model: its card, evaluation and partial-dependence plots on the robot inputs).
"""
from __future__ import annotations

import datetime
import logging
import os
from pathlib import Path

from slam_predict import __version__
from slam_predict.report import html as H
from slam_predict.report.campaign import Campaign, load_campaign
from slam_predict.report.sections import overview, summary, world_section

LOG = logging.getLogger(__name__)


def contents(campaign: Campaign, with_models: bool) -> str:
    """A list of links to the sections."""
    links = [("overview", "Campaign overview"), ("summary", "Per-building summary")]
    links += [(f"world-{name}", f"World {name}") for name in campaign.worlds]
    if with_models:
        links.append(("learning", "Learning"))
    items = "".join(f'<li><a href="#{H.esc(a)}">{H.esc(t)}</a></li>' for a, t in links)
    return f"<nav><ul>{items}</ul></nav>"


def learning(campaign: Campaign, models_path, feature_fn=None, worlds_dir=None) -> str:
    """Model cards and their predictions for the campaign's worlds (a robot-aware model's:
    per run's recorded robot)."""
    from slam_predict.learn.card import card_slam, is_robot_card, slam_label
    from slam_predict.report.models import card_section, load_models
    from slam_predict.report.predictions import FeatureCache, predictions_section
    from slam_predict.report.robot_predictions import robot_predictions_section

    entries = load_models(models_path)
    cache = FeatureCache(campaign, feature_fn, Path(worlds_dir) if worlds_dir else None)
    parts = ["<p>Model cards of the given model folders and their predictions for the "
             "worlds of this campaign (features computed from each world's floor plan with "
             "the model's feature configuration).</p>"]
    ran = campaign_slams(campaign)
    for entry in entries:
        parts.append(card_section(entry))
        trained_for = card_slam(entry.card)
        if ran and trained_for not in ran:
            parts.append(f"<p>{H.esc(entry.name)} predicts the errors of "
                         f"{H.esc(slam_label(trained_for))}; this campaign's runs used "
                         f"{H.esc(', '.join(slam_label(s) for s in sorted(ran)))}: its "
                         "predictions are not compared with them.</p>")
        elif is_robot_card(entry.card):
            parts.append(robot_predictions_section(entry, campaign, cache))
        else:
            parts.append(predictions_section(entry, campaign, cache))
    return H.section("Learning", "\n".join(parts), anchor="learning")


def campaign_slams(campaign: Campaign) -> set[str]:
    """The SLAM algorithms of the campaign's runs (a run naming none ran GMapping)."""
    from slam_predict.learn.robot.records import slam_of_record

    return {slam_of_record(run.record) for run in campaign.runs}


def build_report(data_dir, models_dir=None, title: str | None = None,
                 feature_fn=None, worlds_dir=None) -> str:
    """The report page of campaign ``data_dir`` (HTML text).

    Args:
        data_dir: campaign folder written by ``slam-predict collect``.
        models_dir: a model folder or a folder of them (learning section), or None.
        title: page title (default: from the folder name).
        feature_fn: ``(world name, card) -> features`` override (tests); default: the
            features of the world plan with the card's feature configuration.
        worlds_dir: folder of ``<world>.world`` files searched first for the plans.
    Raises:
        InputError: missing campaign folder, not a campaign, missing/empty models folder.
    """
    campaign = load_campaign(data_dir)
    resolved = Path(data_dir).resolve()
    title = title or f"SLAM campaign report: {resolved.parent.name}/{resolved.name}"
    stamp = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    parts = [f"<p>Generated {H.esc(stamp)} by slam_predict {H.esc(__version__)} from "
             f"<code>{H.esc(os.fspath(data_dir))}</code>.</p>",
             contents(campaign, models_dir is not None), overview(campaign), summary(campaign)]
    learn_html = ("" if models_dir is None
                  else learning(campaign, models_dir, feature_fn, worlds_dir))
    for world in campaign.worlds.values():
        LOG.info("report: world %s", world.name)
        parts.append(world_section(world))
    parts.append(learn_html)
    return H.page(title, "\n".join(parts))
