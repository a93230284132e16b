"""``slam-predict predict PLAN --robot FILE``: the prediction of a robot-aware model.

With a robot description file the four components come from a robot-aware model folder (card
``kind: robots``, :class:`~slam_predict.learn.robot.predict.RobotModel`): ``--model NAME`` (a
folder under ``--models-dir``, or a path), by default ``own-robots``. The robot enters as its
laser range capped at the card's GMapping maxUrange, its field of view and its odometry error
bounds; the output says so and adds the model's domain warnings (robot or plan outside the
training ranges, another laser angular resolution, an odometry pair far from the design).
Without such a folder: a one-line error naming it and how to train one (exit 2).

With ``--simulate`` (:mod:`slam_predict.cli.predict_simulate`) the robot-aware prediction is
printed beside the measured values when the folder exists; otherwise (or when ``--model``
names a plan-only folder) the plan-only one, with the note that it ignores the robot.
"""
from __future__ import annotations

import argparse
import math
import os
from pathlib import Path
from typing import Any

from slam_predict.errors import InputError
from slam_predict.learn.card import DEFAULT_ROBOT_MODEL as DEFAULT_MODEL
from slam_predict.learn.card import ROBOT_KIND, range_cap_name, training_fitted_settings
from slam_predict.learn.card import ROBOT_TRAIN_HINT as TRAIN_HINT
from slam_predict.learn.slam_choice import DEFAULT_SLAM


def model_path(model: str, models_dir: str | None, slam: str = DEFAULT_SLAM) -> Path:
    """The folder ``--model`` names (a path, or the first searched directory holding it);
    ``best``: own-robots for GMapping, else the best robot-aware model trained for ``slam``
    (:func:`slam_predict.learn.slam_choice.find_model`)."""
    from slam_predict.learn.slam_choice import find_model, search_dirs

    if model == "best" and slam != DEFAULT_SLAM:
        return find_model(slam, ROBOT_KIND, "best", models_dir)
    name = DEFAULT_MODEL if model == "best" else model
    if os.sep in name or Path(name).is_dir():
        return Path(name)
    dirs = search_dirs(models_dir)
    return next((d / name for d in dirs if (d / name).exists()), dirs[0] / name)


def load_model(args: argparse.Namespace, required: bool, slam: str = DEFAULT_SLAM):
    """The robot-aware :class:`RobotModel` trained for ``slam`` for ``--robot``, or None when
    ``required`` is False (``--simulate``) and there is none (no folder, or a plan-only one):
    then the plan-only prediction is shown with a note. InputError (one line) otherwise."""
    from slam_predict.learn.card import CARD, kind_of, read_card
    from slam_predict.learn.model import load_model as load_folder
    from slam_predict.learn.slam_choice import check_trained_for

    try:
        path = model_path(args.model, args.models_dir, slam)
    except InputError:
        if not required:
            return None
        raise
    if not (path / CARD).is_file():
        if not required and args.model == "best":
            return None
        raise InputError(f"no robot-aware model folder {path} (needed by --robot): "
                         f"{TRAIN_HINT}")
    if kind_of(read_card(path)) != ROBOT_KIND and not required:
        return None
    model = load_folder(path, ROBOT_KIND)
    check_trained_for(path, slam)
    model.check_feature_version()
    if args.setting:
        raise InputError(f"--thesis-setting applies to the plan-only models: the robot-aware model "
                         f"{model.name} takes the robot itself as input")
    return model


def _entry(raw: dict[str, Any]) -> dict[str, Any]:
    """The reported form of one component (as the plan-only ``predict``'s)."""
    from slam_predict.learn.predict import component_entry

    if raw["value"] is None:
        return {"status": "no_model", "value": None, "low": None, "high": None, "model": None,
                "unit": raw["unit"], "r2": None}
    return component_entry(raw["value"], raw["low"], raw["high"], raw["unit"], raw["model"])


def robot_summary(robot, robot_path: str, model, inputs: dict[str, float]) -> dict[str, Any]:
    """The ``robot`` entry of the result: file, name, the model's inputs, the laser's own
    range (m), the SLAM algorithm's range cap (m: GMapping's maxUrange, Karto's max_laser_range)
    and the laser's angular resolution (deg)."""
    from slam_predict.learn.robot.inputs import angular_resolution_deg, sensor_dict

    return {"file": robot_path, "name": robot.name, "inputs": inputs,
            "laser_range_max_m": float(robot.laser.range_max),
            "max_urange_m": model.max_urange_m,
            "angular_resolution_deg": angular_resolution_deg(sensor_dict(robot), robot_path)}


def predict(world, model, robot, robot_path: str, component: str = "all",
            features: dict[str, float] | None = None) -> dict[str, Any]:
    """The robot-aware prediction for ``world`` (a loaded, checked plan) and ``robot`` (a
    :class:`~slam_predict.robot_file.RobotDescription` read from ``robot_path``): world/
    (free space) → features/ (every feature the model reads; ``features`` when already
    computed) → learn/."""
    from slam_predict.features.plan import plan_features
    from slam_predict.learn.predict import components_of
    from slam_predict.world.plausibility import free_space

    space, unreachable = free_space(world)
    if features is None:
        features = plan_features(world, model.feature_config, model.sightline_config)
    inputs = model.inputs(robot)
    confidence = float(model.card.get("confidence", 0.9))
    raw = model.predict(features, inputs, confidence)
    summary = robot_summary(robot, robot_path, model, inputs)
    if model.derived:
        from slam_predict.learn.robot.inputs import derived_inputs

        summary["derived"] = derived_inputs(features, inputs)
    result: dict[str, Any] = {"world": world.name, "setting": model.card.get("setting"),
                              "model_store": model.name, "model_takes_robot": True,
                              "robot": summary, "confidence": confidence,
                              "fitted_settings": training_fitted_settings(model.card)}
    for comp in components_of(component):
        result[comp] = _entry(raw[comp])
    result["failure"] = failure_entry(model, features, inputs)
    result["training_config_hashes"] = model.card.get("config_hashes")   # not printed
    result["free_space"] = space
    odom_note = model.odom_model_warning(robot.odom_model)
    result["warnings"] = unreachable + list(model.store.notes) + \
        model.domain_warnings(features, inputs, summary["angular_resolution_deg"]) + \
        ([odom_note] if odom_note else [])
    result["features"] = features
    return result


def robot_text(result: dict[str, Any]) -> str:
    """What the robot-aware model took: "laser range 30 m used (laser 80 m, GMapping's
    maxUrange 30 m), fov 270°, beams every 0.5°, odometry 0.01 m/m and 0.0349 rad/rad" (the
    beams when the model reads the angular resolution)."""
    robot = result["robot"]
    inputs = robot["inputs"]
    cap = robot["max_urange_m"]
    used = inputs["laser_range_max_m"]
    cap_name = range_cap_name(result.get("slam", DEFAULT_SLAM))
    laser = (f"laser range {used:g} m used (laser {robot['laser_range_max_m']:g} m, "
             f"{cap_name} {cap:g} m)" if cap is not None and not math.isclose(
                 used, robot["laser_range_max_m"]) else f"laser range {used:g} m")
    blind = robot.get("derived", {}).get("laser_blind_fraction")
    beams = inputs.get("laser_resolution_deg")
    laser += f", fov {inputs['laser_fov_deg']:g}°" + (f", beams every {beams:g}°" if beams else "")
    return (f"{laser}, odometry {inputs['odom_xy_error']:.4g}"
            f" m/m and {inputs['odom_yaw_error']:.4g} rad/rad"
            + (f"; {100 * blind:.3g} % of the plan's sight lines reach no wall within that "
               "range" if blind is not None else ""))


def failure_entry(model, features: dict[str, float],
                  inputs: dict[str, float]) -> dict[str, Any] | None:
    """The ``failure`` entry of the result: the probability that an exploration of the plan
    with the robot maps less than the card's coverage threshold (None: a model folder
    without a failure model)."""
    p = model.failure_probability(features, inputs)
    if p is None:
        return None
    entry = model.failure_entry
    return {"probability": p, "coverage_threshold": float(entry["coverage_threshold"]),
            "training_runs": int(entry["runs"]), "training_failed": int(entry["failed"])}


def failure_text(failure: dict[str, Any] | None) -> list[str]:
    """The failure probability's two lines (none without it)."""
    if failure is None:
        return []
    share = f"{100 * failure['coverage_threshold']:g} %"
    return [f"  failure    P(exploration maps < {share} of the floor)  "
            f"{100 * failure['probability']:.0f} %",
            f"             (learned from {failure['training_runs']} campaign runs, "
            f"{failure['training_failed']} of them failed; the errors above describe "
            "explorations that succeed)"]
