"""``slam-predict predict PLAN --simulate N|auto --out DIR``: measure beside the prediction.

Runs N simulated explorations of PLAN (``auto``: the seed study's run-count rule, a pilot of 10
runs then ⌈z²s²/d²⌉ at 95 % with d_t 0.03 m and d_r 0.002 rad, capped by ``--max-runs``) with
the collection settings (``--settings``) and robot (``--robot``), and prints the measured four
components, each with its 95 % interval (:mod:`slam_predict.metric.intervals`: t for the means,
chi-square for the stds), beside the model's prediction and its 90 % interval: with ``--robot``
that of the robot-aware model when one is installed (:mod:`slam_predict.cli.predict_robot`),
else the plan-only model's, which does not take the robot as input (the output says so).

DIR is a campaign folder (:mod:`slam_predict.collect.simulate`): a second call with the same
arguments redoes no finished run (a larger N adds runs; the statistics use runs 0..N-1); another
plan, ``--seed``, ``--settings`` or ``--robot`` is refused. Every input is checked before
anything is written.
"""
from __future__ import annotations

import argparse
import json
import signal
import sys
from pathlib import Path

from slam_predict.errors import InputError

SIM_OPTIONS = ("out", "seed", "jobs", "max_runs", "settings", "no_progress")
ROBOT_NOTE = "does not take the robot into account"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The --robot and --simulate options of ``predict``."""
    parser.add_argument_group("robot").add_argument(
        "--robot", metavar="YAML|NAME",
        help="robot description file (e.g. config/robots/lds_360_3p5.yaml, or the name of a "
             "shipped one: lds_360_3p5): the prediction comes from a robot-aware model "
             "(--model, default own-robots); with --simulate also the simulated runs' robot")
    group = parser.add_argument_group("simulation (--simulate)")
    group.add_argument("--simulate", metavar="N|auto",
                       help="also run N simulated explorations of PLAN (auto: pilot of 10, "
                            "then the seed study's run-count rule) and print the measured "
                            "components with 95 %% intervals beside the prediction")
    group.add_argument("--out", metavar="DIR",
                       help="folder of the simulated runs (new, empty, or one to resume)")
    group.add_argument("--seed", type=int, help="base seed of the runs (default 0)")
    group.add_argument("--jobs", type=int, help="local worker processes (default 1)")
    group.add_argument("--max-runs", type=int, help="cap for --simulate auto (default 60)")
    group.add_argument("--settings", metavar="YAML",
                       help="collection settings (default config/collect.yaml)")
    group.add_argument("--no-progress", action="store_true", default=None,
                       help="no progress bar")


def check_options(args: argparse.Namespace) -> None:
    """InputError for simulation options given without --simulate, or --simulate without
    --out; fills in the defaults."""
    if args.simulate is None:
        given = [o for o in SIM_OPTIONS if getattr(args, o) is not None]
        if given:
            raise InputError(f"--{given[0].replace('_', '-')} needs --simulate")
        return
    if args.out is None:
        raise InputError("--simulate needs --out DIR")
    from slam_predict.collect.settings import settings_for_slam

    args.settings = settings_for_slam(args.slam, args.settings)   # --slam A: as collect
    defaults = {"seed": 0, "jobs": 1, "max_runs": 60, "no_progress": False}
    for key, value in defaults.items():
        if getattr(args, key) is None:
            setattr(args, key, value)


def _prepare(args: argparse.Namespace, world):
    """Check every simulation input (nothing written); returns (runs, settings, identity)."""
    from slam_predict.cli.collect_cmd import check_start_footprint, parse_runs
    from slam_predict.cli.guards import check_at_least, check_creatable
    from slam_predict.collect.campaign import check_out_folder, identity
    from slam_predict.collect.record import code_version
    from slam_predict.collect.settings import load_settings
    from slam_predict.collect.simulate import check_resume, plan_identity

    runs = parse_runs(args.simulate, "--simulate")
    check_at_least(args.jobs, 1, "--jobs")
    check_at_least(args.max_runs, 1, "--max-runs")
    settings = load_settings(args.settings, robot=args.robot, force_robot=args.force)
    out = Path(args.out)
    check_out_folder(out)
    check_creatable(out)
    check_start_footprint(world, world.provenance.get("source") or world.name,
                          settings.sim.robot.footprint_side)
    current = {**identity(settings, args.seed, code_version()), "plan": plan_identity(world)}
    check_resume(out, current, force=args.force)
    return runs, current


def simulate(args: argparse.Namespace, world, runs, current) -> dict:
    """Run (or resume) the simulations; returns the measured part of the result."""
    from slam_predict.collect.batch import Batch, BatchConfig
    from slam_predict.collect.campaign import open_campaign
    from slam_predict.collect.record import NO_METRIC_NOTE, with_metric
    from slam_predict.collect.simulate import cap_note, measured, write_plan_world
    from slam_predict.collect.summary import write_summary

    out = Path(args.out)
    open_campaign(out, current, force=args.force)
    world_path = write_plan_world(world, out)
    options = {key: getattr(args, key) for key in ("settings", "robot") if getattr(args, key)}
    if args.robot:
        options["force_robot"] = args.force
    config = BatchConfig(runs=runs, max_runs=args.max_runs, jobs=args.jobs,
                         base_seed=args.seed, progress=not args.no_progress, options=options)
    batch = Batch({world.name: str(world_path)}, out, config)
    new = batch.run()
    write_summary(out)
    target = batch.target(world.name)
    done = zip(batch.store.completed(world.name), batch.store.records(world.name), strict=True)
    used = [(index, record) for index, record in done if index < target]
    indices, records = [i for i, _ in used], [r for _, r in used]
    notes = [f"run failed: {failure}" for failure in batch.failures]
    metric_records = with_metric(records)
    if len(metric_records) < len(records):
        notes.append(f"{len(records) - len(metric_records)} of {len(records)} runs measured "
                     f"no error: {NO_METRIC_NOTE}")
    if runs == "auto" and metric_records:
        note = cap_note(metric_records, args.max_runs)
        notes += [note] if note else []
    return {"runs": len(records), "runs_new": new, "run_indices": indices,
            "measured": measured(metric_records) if metric_records else None, "notes": notes,
            "failed": bool(batch.failures), "stopped_by": batch.stopped_by, "records": records}


SETUP_PARTS = ("slam_compute", "stop", "metric")   # config hashes the robot does not change


def setup_note(records, card: dict | None) -> str | None:
    """A note when the simulated runs' robot-independent set-up (GMapping's compute-time
    emulation, the stop rule, the metric) differs from that of the model's training runs
    (card ``config_hashes``): the measured and predicted values then differ by more than the
    model's error. None when they agree, or without records or a card that records them."""
    trained = (card or {}).get("config_hashes") or {}
    differ = []
    for part in SETUP_PARTS:
        if part not in trained:
            continue
        used = {str((r.get("config_hashes") or {}).get(part)) for r in records}
        if not used <= set(map(str, trained[part])):
            differ.append(part)
    if not records or not differ:
        return None
    return (f"the simulated runs' {', '.join(differ)} configuration differs from the model's "
            "training runs' (card config_hashes): pass the settings the model was trained "
            "with (--settings, e.g. config/robot_campaign/settings.yaml for own-robots) to "
            "compare like with like")


def format_text(result: dict, components) -> str:
    """Measured and predicted values per component, then notes and warnings."""
    from slam_predict.cli.plan_checks import plan_line
    from slam_predict.cli.predict_format import (
        LABELS,
        entry_text,
        fitted_lines,
        model_tag,
        slam_label,
        value_text,
    )
    from slam_predict.words import plural

    sim = result["simulation"]
    robot = sim["robot"] or "the settings' robot"
    slam = slam_label(result.get("slam"))
    lines = [f"{result['world']}: {slam} localization error measured over "
             f"{plural(sim['runs'], 'simulated run')} ({sim['runs_new']} new; robot {robot}, "
             f"seed {sim['seed']}, in {sim['out']}), 95 % intervals", plan_line(result["plan"]),
             model_line(result)]
    conf = f"{100 * result['confidence']:g} %"
    for comp in components:
        lines.append(f"  {comp:<10s} {LABELS[comp]}")
        if sim["measured"] is not None:
            m = sim["measured"][comp]
            measured = (f"{value_text(m, '95 %')} [{m['method']}]" if m["status"] == "ok"
                        else f"n/a ({plural(m['runs'], 'run')})")
            lines.append(f"      measured   {measured}")
        e = result[comp]
        lines.append(f"      predicted  {entry_text(e, conf)}{model_tag(e)}")
    if result.get("model_takes_robot"):
        from slam_predict.cli.predict_robot import failure_text

        lines += failure_text(result.get("failure"))
    lines += [f"note: {n}" for n in sim["notes"]]
    lines += fitted_lines(result.get("fitted_settings") or {})
    lines += [f"warning: {w}" for w in result["warnings"]]
    return "\n".join(lines)


def model_line(result: dict) -> str:
    """Which model predicted, and whether it took the robot into account."""
    conf = f"{100 * result['confidence']:g} % intervals"
    if result.get("model_takes_robot"):
        from slam_predict.cli.predict_robot import robot_text

        return (f"model: {result['model_store']} (robot-aware: takes the robot into account; "
                f"{robot_text(result)}), {conf}")
    return f"model: {result['model_store']} ({ROBOT_NOTE}), setting {result['setting']}, {conf}"


def run(args: argparse.Namespace, world, components, predict) -> int:
    """Check the simulation inputs for ``world`` (the loaded, checked plan), predict
    (``predict(world) -> result``), simulate, print both."""
    runs, current = _prepare(args, world)
    result = predict(world)
    sim = simulate(args, world, runs, current)
    if result.get("model_takes_robot"):
        note = setup_note(sim["records"],
                          {"config_hashes": result.get("training_config_hashes")})
        sim["notes"] += [note] if note else []
    result["simulation"] = {"runs": sim["runs"], "runs_new": sim["runs_new"],
                            "run_indices": sim["run_indices"], "seed": args.seed,
                            "robot": args.robot, "settings": args.settings, "out": args.out,
                            "requested": args.simulate, "confidence": 0.95,
                            "measured": sim["measured"], "notes": sim["notes"]}
    result.setdefault("model_takes_robot", False)
    if args.json:
        robot = ["robot", "failure"] if result["model_takes_robot"] else []
        keys = ["world", "plan", "slam", "setting", "model_store", "model_takes_robot", *robot,
                "confidence", "fitted_settings",
                *components, "simulation", "free_space", "warnings", "features"]
        print(json.dumps({k: result[k] for k in keys}, indent=2))
    else:
        print(format_text(result, components))
    if sim["stopped_by"] is not None:
        name = signal.Signals(sim["stopped_by"]).name
        print(f"slam-predict predict: stopped by {name}; the runs in progress were discarded",
              file=sys.stderr)
        return 128 + sim["stopped_by"]
    return 1 if sim["failed"] else 0
