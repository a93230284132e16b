"""``slam-predict predict PLAN``: GMapping's expected localization error from a floor plan.

Prints the four components (mean and std over runs of the mean relation error: translation in
m, rotation in rad and deg), each with its 90 % interval and the model used; ``--json`` prints
one JSON object instead. PLAN is an image (with ``--resolution`` or a map_server YAML beside
it), a map YAML, a Stage .world or a layout XML; ``--world W`` takes the scale and the start
pose from the Stage world W (PLAN may then be omitted: W's own floorplan is used).

``--robot FILE`` (a robot description file) takes the prediction from a robot-aware model
folder, ``own-robots`` unless ``--model`` names another (:mod:`slam_predict.cli.predict_robot`;
no such folder: one-line error, exit 2). ``--simulate N|auto --out DIR`` also runs N simulated
explorations of PLAN (with ``--robot`` and ``--settings``) and prints the measured components
beside the prediction (:mod:`slam_predict.cli.predict_simulate`): the robot-aware one when such
a folder is installed, else the plan-only one with a note that it ignores the robot.
"""
from __future__ import annotations

import argparse
import json
import math

from slam_predict.cli import plan_checks, predict_robot, predict_simulate
from slam_predict.cli.deprecated import add_renamed_option
from slam_predict.cli.predict_format import LABELS, format_text  # noqa: F401  (LABELS re-exported)
from slam_predict.errors import InputError

NAME = "predict"
HELP = "predict GMapping's localization error on a floor plan"
COMPONENT_CHOICES = ("all", "trans_mean", "trans_std", "rot_mean", "rot_std")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from slam_predict.cli.worlds_cmd import add_plan_arguments

    parser.add_argument("plan", metavar="PLAN", nargs="?",
                        help="floor plan: image (.png/.pgm...), map_server .yaml, .world or "
                             "layout .xml")
    parser.add_argument("--world", metavar="W",
                        help="Stage .world giving PLAN's scale and start pose (or the plan "
                             "itself when PLAN is omitted)")
    add_plan_arguments(parser, plan=False)
    parser.add_argument("--component", default="all", metavar="C",
                        help="all (default), trans_mean, trans_std, rot_mean or rot_std")
    parser.add_argument("--model", default="best",
                        help="model folder name under models/ (or a path), default best; "
                             "with --robot a robot-aware one, default own-robots")
    setting = parser.add_argument(
        "--thesis-setting", dest="setting",
        help="the seed study's robot setting (realistic, optimistic) of a plan-only model: with "
             "--model best the default is realistic; with a named model it must match its card")
    add_renamed_option(parser, "--setting", setting)
    parser.add_argument("--models-dir", metavar="DIR", help="model folders (default models/)")
    parser.add_argument("--slam", metavar="NAME",
                        help="the SLAM algorithm whose error is predicted: gmapping (default; "
                             "every shipped model); karto (or slam_toolbox) has no shipped model")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    plan_checks.add_arguments(parser)
    predict_simulate.add_arguments(parser)


def _world_scale(world_path: str, plan: str):
    """(resolution m/px, start (x, y, yaw deg)) for image ``plan`` from Stage world W."""
    from slam_predict.world.bitmap import read_grey
    from slam_predict.world.load import load_plan

    ref = load_plan(world_path)
    rows, cols = read_grey(plan).shape[:2]
    width, height = ref.size_m
    res_x, res_y = width / cols, height / rows
    if abs(res_x - res_y) > 0.01 * res_x:
        raise InputError(f"the world's floorplan size {width:g} x {height:g} m does not keep "
                         f"the aspect ratio of {plan} ({cols} x {rows} px)", world_path)
    x, y, yaw = ref.start_pose
    return res_x, [float(x), float(y), math.degrees(yaw)]


def load_world(args: argparse.Namespace):
    """The World to predict on, from PLAN and/or --world and the plan options."""
    from slam_predict.cli.worlds_cmd import load_plan_from_args

    if args.world and args.resolution is not None:
        raise InputError("give either --world or --resolution, not both")
    if args.plan is None and args.world is None:
        raise InputError("give a floor plan (PLAN) or --world W")
    if args.world and (args.plan is None or args.plan.lower().endswith(".world")):
        if args.plan is not None and args.plan != args.world:
            raise InputError("give either a .world PLAN or --world, not both")
        return load_plan_from_args(argparse.Namespace(**{**vars(args), "plan": args.world}))
    if args.world:
        from slam_predict.errors import require_file

        require_file(args.plan, "plan")
        resolution, start = _world_scale(require_file(args.world, "world"), args.plan)
        changes = {"resolution": resolution, "start": args.start or start}
        return load_plan_from_args(argparse.Namespace(**{**vars(args), **changes}))
    return load_plan_from_args(args)


def predict_plan(world, args: argparse.Namespace, setting: str | None) -> dict:
    """The plan-only prediction for ``world`` (a loaded, checked plan): world/ (free space) →
    features/ (the card's feature configuration) → learn/ (the ``--model`` folder)."""
    from slam_predict.features.plan import plan_features
    from slam_predict.learn.model import PlanModel, resolve_store
    from slam_predict.learn.store import default_models_dir
    from slam_predict.slam import canonical_name
    from slam_predict.world.plausibility import free_space

    slam = canonical_name(args.slam) if args.slam else None
    model = PlanModel(resolve_store(args.models_dir or default_models_dir(), args.model,
                                    setting, None, slam))
    model.check_feature_version()
    space, unreachable = free_space(world)
    features = plan_features(world, model.feature_config)
    result = model.predict(features, component=args.component)
    result["free_space"] = space
    result["warnings"] = unreachable + result["warnings"]
    result["world"] = world.name
    result["features"] = features
    return result


def check_slam_option(name: str | None, models_dir: str | None = None) -> None:
    """InputError (one line, what to do) unless ``--slam`` names an algorithm a model of
    ``models_dir`` (default models/) was trained on."""
    from slam_predict.learn.model import trained_slams
    from slam_predict.learn.store import default_models_dir
    from slam_predict.slam import canonical_name

    if name is None:
        return
    name = canonical_name(name)
    trained = trained_slams(models_dir or default_models_dir())
    if name in trained:
        return
    raise InputError(f"--slam {name}: no model of {name}'s error is shipped (every model was "
                     f"trained on {', '.join(trained) or 'gmapping'} runs); to make one, collect "
                     f"{name} runs (slam-predict collect WORLDS --slam {name} --out DATA) and "
                     f"train on them (slam-predict learn dataset, learn train --slam {name}; "
                     "docs/howto/slam-backend.md)")


def run(args: argparse.Namespace) -> int:
    from slam_predict.learn.predict import components_of

    components = components_of(args.component)  # before the (slow) feature computation
    check_slam_option(args.slam, args.models_dir)
    predict_simulate.check_options(args)
    setting = args.setting or ("realistic" if args.model == "best" else None)
    robot = robot_model = None
    if args.robot:
        from slam_predict.robot_file import load_robot

        robot = load_robot(args.robot, force=args.force)  # a bad robot file is the first error
        robot_model = predict_robot.load_model(args, required=args.simulate is None)

    def predict(world) -> dict:
        plan_checks.show_progress()
        if robot_model is not None:
            return predict_robot.predict(world, robot_model, robot, args.robot, args.component)
        return predict_plan(world, args, setting)

    world = plan_checks.load_checked(load_world, args)
    plan = plan_checks.plan_used(world, args)
    if args.simulate is not None:
        return predict_simulate.run(args, world, components,
                                    lambda w: {**predict(w), "plan": plan})
    result = {**predict(world), "plan": plan}
    if args.json:
        robot_keys = (["model_takes_robot", "robot", "failure"] if robot_model is not None
                      else [])
        keys = ["world", "plan", "setting", "model_store", *robot_keys, "confidence",
                *components, "free_space", "warnings", "features"]
        print(json.dumps({k: result[k] for k in keys}, indent=2))
    else:
        print(format_text(result, components))
    return 0
