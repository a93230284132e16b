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


def expected_hashes(sources: dict, record: dict, cache: dict) -> dict:
    """The hashes the card's settings file (and, for a design run, its design point's robot)
    resolves to."""
    key = record.get("design", {}).get("config")
    if key not in cache:
        settings = load_settings(PROJECT_ROOT / sources["settings"])
        if key is not None:
            design = load_design(PROJECT_ROOT / sources["design"])
            settings = design.settings_for(settings, key, sources["design"])
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
            if record["config_hashes"] != expected_hashes(sources, record, cache):
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
    assert record["config_hashes"] == expected_hashes(sources, record, {})
    assert record["config_hashes"] != expected_hashes({**sources, "settings": str(changed)},
                                                      record, {})


@pytest.mark.parametrize("name", OWN)
def test_own_model_cards_carry_their_settings_fitted_values(name):
    """A card's sources.fitted is what its settings file declares fitted, word for word: the
    file is the one copy, the card what predict shows."""
    sources = read_card(MODELS / name)["sources"]
    assert sources.get("fitted") == fitted_settings(PROJECT_ROOT / sources["settings"])
    assert sources["fitted"], f"{name}: its chain's fitted rebuild cost is not on the card"
