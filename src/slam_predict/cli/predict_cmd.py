"""``slam-predict predict PLAN``: a SLAM algorithm's expected localization error from a plan.

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

``--slam A`` predicts with the model whose card says it was trained for SLAM algorithm A
(default gmapping; :mod:`slam_predict.learn.slam_choice`); ``--compare A B`` predicts for both
side by side and says which is expected to be more accurate
(:mod:`slam_predict.cli.predict_compare`).
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
HELP = "predict a SLAM algorithm's localization error on a floor plan (default GMapping)"
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
                        help="the SLAM algorithm whose error is predicted, by the model whose "
                             "card says it was trained for it: gmapping (default; every shipped "
                             "model) or karto (also spelt slam_toolbox; no shipped model)")
    parser.add_argument("--compare", nargs=2, metavar=("A", "B"),
                        help="predict for SLAM algorithms A and B side by side (e.g. gmapping "
                             "karto), each by its own model, and say which is expected to be more "
                             "accurate here (lower mean translational error) and how sure that "
                             "is; 'too close to call' below a probability of 0.75")
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


def predict_plan(world, model, component: str = "all",
                 features: dict[str, float] | None = None) -> dict:
    """The plan-only prediction of ``model`` (a loaded plan-only model) for ``world`` (a
    loaded, checked plan): world/ (free space) → features/ (the card's feature configuration;
    ``features`` when already computed) → learn/."""
    from slam_predict.features.plan import plan_features
    from slam_predict.world.plausibility import free_space

    space, unreachable = free_space(world)
    if features is None:
        features = plan_features(world, model.feature_config)
    result = model.predict(features, component=component)
    result["free_space"] = space
    result["warnings"] = unreachable + result["warnings"]
    result["world"] = world.name
    result["features"] = features
    return result


def algorithms_of(args: argparse.Namespace) -> list[str]:
    """The SLAM algorithms to predict for: --compare's two, else --slam's (default gmapping);
    InputError (one line) for an unknown name or an option --compare does not take."""
    from slam_predict.learn.slam_choice import DEFAULT_SLAM
    from slam_predict.slam import canonical_name

    if not args.compare:
        return [canonical_name(args.slam) if args.slam else DEFAULT_SLAM]
    names = [canonical_name(name, "--compare") for name in args.compare]
    if args.slam:
        raise InputError("give either --slam or --compare, not both")
    if names[0] == names[1]:
        raise InputError(f"--compare {' '.join(args.compare)}: name two different SLAM "
                         "algorithms")
    if args.model != "best":
        raise InputError("--compare takes each algorithm's own model (the one whose card says "
                         "it was trained for it): give no --model")
    if args.simulate is not None:
        raise InputError("--compare only predicts: simulate one algorithm at a time "
                         "(--slam A --simulate N)")
    return names


def load_models(args: argparse.Namespace, algorithms: list[str], setting: str | None) -> dict:
    """{algorithm: the model that predicts its error}: robot-aware with --robot (None under
    --simulate when there is none: the plan-only one then), else plan-only."""
    from slam_predict.learn.model import PlanModel, resolve_store

    models = {}
    for slam in algorithms:
        try:
            model = predict_robot.load_model(args, args.simulate is None, slam) \
                if args.robot else None
            if model is None:
                model = PlanModel(resolve_store(args.models_dir, args.model, setting, None, slam))
                model.check_feature_version()
        except InputError as exc:
            if not (args.slam or args.compare):
                raise
            option = f"--compare {' '.join(algorithms)}" if args.compare else f"--slam {slam}"
            raise InputError(f"{option}: {exc.problem}", exc.path) from None
        models[slam] = model
    return models


def predictor(args: argparse.Namespace, robot, component: str):
    """predict(world, model, features=None) → the result of one model, robot-aware or not."""
    def predict(world, model, features=None) -> dict:
        if model.takes_robot:
            return predict_robot.predict(world, model, robot, args.robot, component, features)
        return predict_plan(world, model, component, features)
    return predict


def run(args: argparse.Namespace) -> int:
    from slam_predict.learn.predict import components_of

    components = components_of(args.component)  # before the (slow) feature computation
    algorithms = algorithms_of(args)
    predict_simulate.check_options(args)
    setting = args.setting or ("realistic" if args.model == "best" else None)
    robot = None
    if args.robot:
        from slam_predict.robot_file import load_robot

        robot = load_robot(args.robot, force=args.force)  # a bad robot file is the first error
    models = load_models(args, algorithms, setting)
    if args.compare:
        from slam_predict.cli import predict_compare

        world = plan_checks.load_checked(load_world, args)
        plan_checks.show_progress()
        return predict_compare.run(args, world, models, predictor(args, robot, "all"),
                                   components)
    slam, model = algorithms[0], models[algorithms[0]]
    predict = predictor(args, robot, args.component)

    def predict_world(world) -> dict:
        plan_checks.show_progress()
        return {**predict(world, model), "slam": slam}

    world = plan_checks.load_checked(load_world, args)
    plan = plan_checks.plan_used(world, args)
    if args.simulate is not None:
        return predict_simulate.run(args, world, components,
                                    lambda w: {**predict_world(w), "plan": plan})
    result = {**predict_world(world), "plan": plan}
    if args.json:
        robot_keys = (["model_takes_robot", "robot", "failure"] if model.takes_robot else [])
        keys = ["world", "plan", "slam", "setting", "model_store", *robot_keys, "confidence",
                "fitted_settings", *components, "free_space", "warnings", "features"]
        print(json.dumps({k: result[k] for k in keys}, indent=2))
    else:
        print(format_text(result, components))
    return 0
