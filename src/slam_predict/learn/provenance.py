"""Where a model's training data came from: the campaign folders and their settings file.

A trained card's ``sources`` name the campaigns (``data``: project-relative folders) and the
settings file of record (``settings``: the file whose resolved settings every run of those
campaigns recorded, from each campaign's campaign.json; ``{campaign: file}`` when the
campaigns were collected with different files) with, as ``fitted``, the settings that
file declares fitted to the seed study rather than measured
(:func:`slam_predict.collect.settings.fitted_settings`; ``predict`` shows them).
tests/learn/test_shipped_model_campaigns.py checks that every run of a shipped own model's
campaigns recorded that file's settings hashes.
"""
from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

from slam_predict.collect.campaign import CAMPAIGN_JSON, recorded_settings_file
from slam_predict.collect.settings import fitted_settings
from slam_predict.paths import PROJECT_ROOT, portable_path


def campaign_folder(errors_table: os.PathLike | str) -> Path | None:
    """The campaign folder of a ``summary.csv`` (its parent, when a campaign.json or a run
    folder sits beside it), else None (e.g. the seed study's own table)."""
    folder = Path(errors_table).resolve().parent
    if (folder / CAMPAIGN_JSON).is_file() or any(folder.glob("*/run_*/run.json")):
        return folder
    return None


def campaign_sources(folders: Sequence[os.PathLike | str]) -> dict[str, object]:
    """``{"data": [folders], "settings": ..., "fitted": {...}}`` for a card's sources.

    ``settings`` is the one settings file every folder's campaign.json names, or, when they
    name different files, ``{folder: file}``; absent when a folder has no campaign.json.
    ``fitted`` joins those files' fitted settings (:func:`fitted_settings`; only files found,
    and only when any declares one)."""
    data = [portable_path(f) for f in folders]
    recorded = {name: recorded_settings_file(folder)
                for folder, name in zip(folders, data, strict=True)}
    out: dict[str, object] = {"data": data}
    files = set(recorded.values())
    if None in files:
        return out
    out["settings"] = files.pop() if len(files) == 1 else recorded
    fitted: dict[str, str] = {}
    for file in sorted(set(recorded.values())):
        if (PROJECT_ROOT / file).is_file():
            fitted.update(fitted_settings(PROJECT_ROOT / file))
    if fitted:
        out["fitted"] = fitted
    return out
