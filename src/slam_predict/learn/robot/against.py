"""Leave-one-building-out predictions of a robot-aware model, scored against another study.

The robot-aware counterpart of :mod:`slam_predict.learn.against`: for every building whose
point of one robot configuration (e.g. the seed study's robot, as the fidelity campaign
collected it) is in the tables and in the other table (e.g. the seed study's measured mean
ε_t), the card's model kind is refitted on every point of the *other* buildings (all robot
configurations; :func:`~slam_predict.learn.robot.models.fit_component`, with its CV+
calibration) and predicts that point. The score is the prediction's percentage error against
the other table's value, not against our own measurement (kept as ``ours``).
"""
from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from slam_predict.errors import InputError
from slam_predict.learn.against import scored_against
from slam_predict.learn.robot.config import RobotLearningConfig
from slam_predict.learn.robot.evaluate import Split, prediction_rows
from slam_predict.learn.robot.models import fit_component
from slam_predict.learn.robot.rundata import RobotTables

PROTOCOL = "one building"


def building_splits(tables: RobotTables, config_id: str, worlds) -> list[Split]:
    """One split per building of ``worlds`` with a point of ``config_id``: that point is the
    test, every point of the other buildings the training set."""
    splits = []
    for world in sorted(set(worlds)):
        test = np.flatnonzero((tables.point_world == world) & (tables.point_config == config_id))
        if len(test):
            train = np.flatnonzero(tables.point_world != world)
            splits.append(Split(PROTOCOL, world, train, test))
    return splits


def leave_one_building_out_against(tables: RobotTables, config: RobotLearningConfig,
                                   chosen: Mapping[str, str], config_id: str,
                                   truth: Mapping[str, Mapping[str, float]],
                                   n_jobs: int = 1) -> list[dict]:
    """Rows (component, model, world, ours, prediction, low, high, y = theirs, covered,
    pct_error) of the points of configuration ``config_id`` of every building in ``truth``,
    each predicted by ``chosen`` (component → model kind) refitted without its building;
    InputError when no building qualifies."""
    from joblib import Parallel, delayed

    splits = building_splits(tables, config_id, [w for w in tables.point_world if w in truth])
    if not splits:
        raise InputError(f"no building has both a point of configuration '{config_id}' and a "
                         "row in the other table")
    chunks = Parallel(n_jobs=n_jobs)(delayed(_predict_split)(tables, s, config, chosen)
                                     for s in splits)
    rows = [scored_against(row, float(truth[row["world"]][row["component"]]))
            for chunk in chunks for row in chunk]
    return sorted(rows, key=lambda r: (list(chosen).index(r["component"]), r["world"]))


def _predict_split(tables: RobotTables, split: Split, config: RobotLearningConfig,
                   chosen: Mapping[str, str]) -> list[dict]:
    train = tables.subset(split.train)
    rows: list[dict] = []
    for component, kind in chosen.items():
        model = fit_component(train, component, kind, config)
        rows += prediction_rows(tables, split, component, kind, model, config.confidence)
    return rows


def load_card_tables(model: str, data_dirs, worlds_dir, n_jobs: int = 1):
    """(card, its RobotLearningConfig, RobotTables) of the robot-aware model ``model`` (a
    name under the models folder or a folder) over the runs of ``data_dirs``, with the plan
    features computed on ``worlds_dir`` under the card's feature configuration; InputError
    for a plan-only card or features of another version."""
    from slam_predict.config import from_dict
    from slam_predict.learn.card import DEFAULT_SLAM, ROBOT_KIND, check_kind, read_card
    from slam_predict.learn.robot.rundata import learning_data
    from slam_predict.learn.slam_choice import find_model
    from slam_predict.learn.store import default_models_dir

    folder = find_model(DEFAULT_SLAM, ROBOT_KIND, model, default_models_dir())
    card = read_card(folder)
    check_kind(card, ROBOT_KIND, folder / "card.json")
    # cards from before the resolution input learnt four robot inputs
    config = from_dict(RobotLearningConfig,
                       {"resolution_input": False, **card["robot_learning_config"]}, "model card")
    data, _, _ = learning_data(data_dirs, config, card.get("slam") or DEFAULT_SLAM,
                               worlds_dir=worlds_dir, feature_config=card["feature_config"],
                               n_jobs=n_jobs)
    if data.feature_version != card["feature_version"]:
        raise InputError(f"features of version {data.feature_version}, the card's are "
                         f"{card['feature_version']}", worlds_dir)
    return card, config, data.config_tables(config)


def robot_of_campaigns(campaigns, config: RobotLearningConfig, card) -> str:
    """The one robot configuration (id as the learner names it) of the runs of
    ``campaigns``; InputError when they hold none or several."""
    from slam_predict.learn.card import DEFAULT_SLAM
    from slam_predict.learn.robot.records import read_runs

    runs, _ = read_runs(campaigns, config.min_coverage, config.max_urange_m,
                        card.get("slam") or DEFAULT_SLAM)
    configs = sorted({r.config for r in runs})
    if len(configs) != 1:
        raise InputError(f"the compared campaigns hold {len(configs)} robot configurations "
                         f"({', '.join(configs[:4])}); compare one robot's campaign",
                         campaigns[0])
    return configs[0]
