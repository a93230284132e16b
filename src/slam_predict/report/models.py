"""Model folders for the report's learning section: loading and the model-card tables.

``--models-dir`` names either one model folder (``card.json`` inside) or a folder of them (like
the shipped ``models/``). A card that cannot be read, or a folder whose files fail the store's
checks (checksums, scikit-learn major version), is reported on the page; the other models are
still shown. Every folder is loaded with :func:`slam_predict.learn.model.load_model`; a
robot-aware one (card ``kind: robots``) is shown by
:mod:`slam_predict.report.robot_models` (its card, evaluation and partial-dependence plots).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from slam_predict.errors import InputError
from slam_predict.learn.card import fitted_summary
from slam_predict.learn.dataset import COMPONENTS, UNITS
from slam_predict.learn.store import skilful
from slam_predict.report import html as H
from slam_predict.report.labels import LABELS  # noqa: F401  (re-exported for report.predictions)

METRIC_COLUMNS = ("R² mean", "R² std", "R² median", "RMSE", "NRMSE", "NRMSE (all)",
                  "mean % error", "LOO coverage", "LOO interval width", "LOO R²")


@dataclass
class ModelEntry:
    """One model folder: its card (None if unreadable), the usable store and the problems."""

    path: Path
    card: dict[str, Any] | None = None
    store: Any = None     # the loaded model: PlanModel or RobotModel
    notes: list[str] = field(default_factory=list)

    @property
    def name(self) -> str:
        return str(self.card.get("name", self.path.name)) if self.card else self.path.name


def load_models(path) -> list[ModelEntry]:
    """The model folders under ``path``; InputError if it is missing or holds no model."""
    from slam_predict.learn.store import CARD, list_stores

    root = Path(path)
    if not root.is_dir():
        raise InputError("models folder not found", root)
    folders = [root] if (root / CARD).is_file() else list_stores(root)
    if not folders:
        raise InputError("no model folder (with card.json) found", root)
    return [load_entry(folder) for folder in folders]


def load_entry(folder: Path) -> ModelEntry:
    """Read one model folder; problems become notes. ``store``: the loaded model
    (:func:`slam_predict.learn.model.load_model`)."""
    from slam_predict.learn.card import read_card
    from slam_predict.learn.model import load_model

    entry = ModelEntry(folder)
    try:
        entry.card = read_card(folder)
        model = load_model(folder)
        model.check_feature_version()
    except InputError as exc:
        entry.notes.append(f"model not usable for predictions: {exc.one_line()}")
        return entry
    entry.store = model
    entry.notes += model.notes
    return entry


def _metric(metrics: dict[str, Any], key: str, digits: int) -> H.Cell:
    value = metrics.get(key)
    return H.num_cell(value, digits)


def metrics_row(component: str, model_id: str, entry: dict[str, Any]) -> list:
    """One row of the card's metrics table."""
    m = entry.get("metrics", {})
    loo = m.get("leave_one_out", {})
    unit_digits = 4 if UNITS[component] == "m" else 5
    features = entry.get("features_used", [])
    shown = ", ".join(features[:4]) + (f" (+{len(features) - 4} more)" if len(features) > 4
                                       else "")
    return [component, UNITS[component], model_id, shown or H.MISSING,
            _metric(m, "r2_mean", 3), _metric(m, "r2_std", 3), _metric(m, "r2_median", 3),
            _metric(m, "rmse_mean", unit_digits), _metric(m, "nrmse_mean", 3),
            _metric(m, "nrmse_all_mean", 3), H.num_cell(_percent(m.get("pct_error_mean")), 1),
            H.num_cell(loo.get("coverage"), 3), H.num_cell(loo.get("width_mean"), unit_digits),
            H.num_cell(loo.get("r2"), 3)]


def _percent(value) -> float:
    try:
        return 100.0 * float(value)
    except (TypeError, ValueError):
        return math.nan


def metrics_table(card: dict[str, Any]) -> str:
    """Every stored model of every component with its evaluation scores; the best in bold."""
    rows, classes = [], []
    for component in COMPONENTS:
        comp = card.get("components", {}).get(component)
        if not isinstance(comp, dict):
            continue
        for model_id, entry in comp.get("models", {}).items():
            rows.append(metrics_row(component, model_id, entry if isinstance(entry, dict)
                                    else {}))
            classes.append("best" if model_id == comp.get("best") and isinstance(entry, dict)
                           and skilful(entry.get("metrics") or {}) else "")
    header = ["component", "unit", "model", "features used", *METRIC_COLUMNS]
    return H.table(header, rows, row_classes=classes)


def card_overview(card: dict[str, Any]) -> str:
    """Key facts of a card: what the models were trained on and with which libraries."""
    buildings = card.get("training_buildings", [])
    versions = card.get("versions", {})
    pairs = [("description", card.get("description", "") or H.MISSING),
             ("setting", card.get("setting", H.MISSING)),
             ("SLAM config hash", card.get("slam_config_hash") or "not recorded"),
             ("feature version", card.get("feature_version", H.MISSING)),
             ("features", len(card.get("features", []))),
             ("training buildings", len(buildings)),
             ("interval confidence", card.get("confidence", H.MISSING)),
             ("fitted collection settings", fitted_summary(card)),
             ("created", card.get("created", H.MISSING)),
             ("libraries", ", ".join(f"{k} {v}" for k, v in versions.items()) or H.MISSING)]
    listing = H.details(f"the {len(buildings)} training buildings",
                        "<p>" + H.esc(", ".join(map(str, buildings))) + "</p>")
    return H.key_values(pairs) + listing


def card_section(entry: ModelEntry) -> str:
    """The model card: overview, metrics table (scores of the evaluation on the training
    buildings: repeated random splits and leave-one-building-out) and the folder's notes; a
    robot-aware folder's is :func:`slam_predict.report.robot_models.robot_card_section`."""
    from slam_predict.learn.card import is_robot_card
    from slam_predict.report.robot_models import robot_card_section

    if is_robot_card(entry.card):
        return robot_card_section(entry)
    if entry.card is None:
        return H.section(f"Model {entry.name}", H.notes(entry.notes), level=3)
    body = (card_overview(entry.card)
            + "<p>Scores from the model's evaluation on its training buildings (mean over "
              "random train/test splits; LOO = leave one building out; best model per "
              "component in bold, unless an R² is ≤ 0: such a model predicts no better than "
              "the training mean and is not used). Errors in m (translation) and rad "
              "(rotation).</p>"
            + metrics_table(entry.card) + H.notes(entry.notes))
    return H.section(f"Model {entry.name}", body, level=3, anchor=f"model-{entry.name}")
