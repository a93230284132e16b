"""Two small plan-only models for ``predict --compare`` tests, trained on the project's campaigns.

Each is trained by the project's own training code on one campaign's measured errors
(data/campaigns/<campaign>/summary.csv) joined with the plan features of its buildings as the
shipped own-robots model recorded them (models/own-robots/training_points.csv: building area
and Voronoi traversal distance, computed from the real plans under the card's feature
configuration, which the model cards name so that ``predict`` computes the same features on a
new plan). The second model's card is relabelled (``slam: karto``) as if its campaign had been
collected with Karto: it then stands for a Karto model.
"""
from __future__ import annotations

import csv
import json
import shutil
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
POINTS = ROOT / "models" / "own-robots" / "training_points.csv"
FEATURES = ("building_area", "voronoi_traversal_distance")
LEARNING = {"models": ["single", "elasticnet"],
            "elasticnet": {"alphas": [0.001, 0.01, 0.1], "l1_ratios": [0.5, 1.0]},
            "conformal": {"cv": 3}, "evaluation": {"n_splits": 3}}


def plan_features() -> dict[str, dict[str, float]]:
    """{building: its plan features} from the own-robots training points."""
    with open(POINTS, newline="") as handle:
        return {row["world"]: {f: float(row[f]) for f in FEATURES}
                for row in csv.DictReader(handle)}


def own_robots_card() -> dict:
    return json.loads((ROOT / "models" / "own-robots" / "card.json").read_text())


def train(models_dir: Path, name: str, campaign: str, slam: str | None = None,
          scale: float = 1.0) -> Path:
    """``models_dir/name`` trained on ``campaign``'s errors (times ``scale``), its card
    relabelled to ``slam`` when given."""
    from slam_predict.collect.fidelity_parts import load_parts
    from slam_predict.config import from_dict
    from slam_predict.learn import dataset as ds
    from slam_predict.learn.config import LearningConfig
    from slam_predict.learn.results import run_evaluation
    from slam_predict.learn.sources import read_error_table
    from slam_predict.learn.train import train_store

    card = own_robots_card()
    folder = ROOT / "data" / "campaigns" / campaign
    rows = read_error_table(folder / "summary.csv", "realistic")
    if (folder / "parts.yaml").is_file():   # a growing campaign: the buildings of its first part
        first = next(iter(load_parts(folder / "parts.yaml").values()))
        rows = [row for row in rows if row.world in first]
    for row in rows:
        row.targets = {k: v * scale for k, v in row.targets.items()}
    data = ds.join(rows, plan_features(), card["feature_version"])
    config = from_dict(LearningConfig, LEARNING)
    folder = train_store(data, config, run_evaluation(data, config), name, models_dir,
                         f"test model: {campaign}", feature_config=card["feature_config"])
    return relabel(folder, slam=slam) if slam is not None else folder


def relabel(folder: Path, **card_changes) -> Path:
    """Change entries of the card of model ``folder`` (its files' checksums stay valid)."""
    path = folder / "card.json"
    path.write_text(json.dumps({**json.loads(path.read_text()), **card_changes}, indent=2))
    return folder


def copy_as(source: Path, target: Path, slam: str) -> Path:
    """A copy of model folder ``source`` at ``target``, named after it, labelled ``slam``."""
    shutil.copytree(source, target)
    return relabel(target, slam=slam, name=target.name)
