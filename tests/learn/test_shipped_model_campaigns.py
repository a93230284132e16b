"""Every shipped own model was trained on campaigns collected with the shipped settings.

A card's ``sources`` name its campaigns (``data``) and the settings file of record
(``settings``; with ``design``, each run's robot is its design point's). Every run.json of
those campaigns must have recorded the settings hashes that file resolves to today: a changed
settings file (or a campaign collected with other settings) fails here until the model is
retrained on a campaign of the shipped settings.
"""
import json

import pytest

from slam_predict.collect.robot_design import load_design
from slam_predict.collect.settings import fitted_settings, load_settings
from slam_predict.learn.card import read_card
from slam_predict.paths import PROJECT_ROOT

MODELS = PROJECT_ROOT / "models"
OWN = sorted(p.name for p in MODELS.iterdir() if p.name.startswith("own-"))


def settings_file(sources: dict, campaign: str) -> str:
    """The card's settings file of ``campaign`` (one file, or one per campaign)."""
    settings = sources["settings"]
    return settings[campaign] if isinstance(settings, dict) else settings


def expected_hashes(sources: dict, record: dict, cache: dict, campaign: str) -> dict:
    """The hashes the campaign's settings file (and, for a design run, its design point's
    robot) resolves to."""
    file = settings_file(sources, campaign)
    key = (file, record.get("design", {}).get("config"))
    if key not in cache:
        settings = load_settings(PROJECT_ROOT / file)
        if key[1] is not None:   # the design file (of the card's one or more) with the point
            files = sources["design"]
            path = next(p for p in ([files] if isinstance(files, str) else files)
                        if key[1] in load_design(PROJECT_ROOT / p).configs)
            settings = load_design(PROJECT_ROOT / path).settings_for(settings, key[1], path)
        cache[key] = settings.hashes()
    return cache[key]


def test_there_are_own_models():
    assert OWN == ["own-realistic", "own-robots"]


@pytest.mark.parametrize("name", OWN)
def test_own_model_campaigns_match_the_shipped_settings(name):
    sources = read_card(MODELS / name)["sources"]
    assert sources.get("data") and sources.get("settings"), \
        f"{name}: the card must name its campaigns (sources.data) and settings (sources.settings)"
    cache: dict = {}
    runs, wrong = 0, []
    for campaign in sources["data"]:
        records = sorted((PROJECT_ROOT / campaign).glob("*/run_*/run.json"))
        assert records, f"{campaign}: no run records"
        for path in records:
            record = json.loads(path.read_text())
            runs += 1
            if record["config_hashes"] != expected_hashes(sources, record, cache, campaign):
                wrong.append(str(path.relative_to(PROJECT_ROOT)))
    assert not wrong, f"{name}: {len(wrong)} of {runs} runs have other settings: {wrong[:3]}"


def test_a_changed_settings_file_is_caught(tmp_path):
    """The check fails for settings that differ in one value (the stop rule's threshold)."""
    sources = read_card(MODELS / "own-realistic")["sources"]
    changed = tmp_path / "settings.yaml"
    changed.write_text(f"extends: {PROJECT_ROOT / sources['settings']}\nstop:\n"
                       "  mse_threshold: 11.0\n")
    record = json.loads(next((PROJECT_ROOT / sources["data"][0]).glob(
        "*/run_*/run.json")).read_text())
    campaign = sources["data"][0]
    assert record["config_hashes"] == expected_hashes(sources, record, {}, campaign)
    assert record["config_hashes"] != expected_hashes({**sources, "settings": str(changed)},
                                                      record, {}, campaign)


@pytest.mark.parametrize("name", OWN)
def test_own_model_cards_carry_their_settings_fitted_values(name):
    """A card's sources.fitted is what its settings file declares fitted, word for word: the
    file is the one copy, the card what predict shows."""
    sources = read_card(MODELS / name)["sources"]
    declared: dict = {}
    for campaign in sources["data"]:
        declared.update(fitted_settings(PROJECT_ROOT / settings_file(sources, campaign)))
    assert sources.get("fitted") == declared
    assert sources["fitted"], f"{name}: its chain's fitted rebuild cost is not on the card"
