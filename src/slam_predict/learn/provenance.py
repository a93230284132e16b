"""Where a model's training data came from: the campaign folders and their settings file.

A trained card's ``sources`` name the campaigns (``data``: project-relative folders) and the
settings file of record (``settings``: the file whose resolved settings every run of those
campaigns recorded, from each campaign's campaign.json) with, as ``fitted``, the settings that
file declares fitted to the seed study rather than measured
(:func:`slam_predict.collect.settings.fitted_settings`; ``predict`` shows them).
tests/learn/test_shipped_model_campaigns.py checks that every run of a shipped own model's
campaigns recorded that file's settings hashes.
"""
from __future__ import annotations

import json
import os
from collections.abc import Sequence
from pathlib import Path

from slam_predict.collect.campaign import CAMPAIGN_JSON
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
    """``{"data": [folders], "settings": file, "fitted": {...}}`` for a card's sources;
    ``settings`` and ``fitted`` only when every folder's campaign.json names the same settings
    file (``fitted`` only when that file is found and declares any)."""
    files = set()
    for folder in folders:
        path = Path(folder) / CAMPAIGN_JSON
        recorded = json.loads(path.read_text()).get("settings_file") if path.is_file() else None
        files.add(recorded)
    out: dict[str, object] = {"data": [portable_path(f) for f in folders]}
    if len(files) == 1 and None not in files:
        out["settings"] = files.pop()
        file = PROJECT_ROOT / str(out["settings"])
        fitted = fitted_settings(file) if file.is_file() else {}
        if fitted:
            out["fitted"] = fitted
    return out
