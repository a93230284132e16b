"""Text forms of ``predict``'s result: one line per component (value, interval, model).

Shared by ``predict`` (:mod:`slam_predict.cli.predict_cmd`, with ``--robot``
:mod:`slam_predict.cli.predict_robot`) and ``predict --simulate``
(:mod:`slam_predict.cli.predict_simulate`); lengths in m, angles in rad and deg.
"""
from __future__ import annotations

import math

from slam_predict.learn.card import slam_label

LABELS = {"trans_mean": "mean translational error", "trans_std": "std of translational error",
          "rot_mean": "mean rotational error", "rot_std": "std of rotational error"}


def interval_text(entry: dict, digits: int) -> str:
    return f"{entry['low']:.{digits}f}–{entry['high']:.{digits}f}"


def value_text(e: dict, conf: str) -> str:
    """"0.123 m (90 % interval 0.05–0.2 m)" or the rotation form in rad and deg."""
    if e["unit"] == "m":
        text = f"{e['value']:.3f} m"
        return text + (f" ({conf} interval {interval_text(e, 3)} m)" if e["low"] is not None
                       else " (no interval)")
    deg = {k: math.degrees(e[k]) for k in ("value", "low", "high") if e[k] is not None}
    text = f"{e['value']:.4f} rad = {deg['value']:.2f} deg"
    if e["low"] is None:
        return text + " (no interval)"
    return text + f" ({conf} interval {interval_text(e, 4)} rad = {interval_text(deg, 2)} deg)"


def entry_text(e: dict, conf: str) -> str:
    """The value part of one component's line, whatever its status."""
    if e["status"] == "no_model":
        return "no model (none beats the training mean)"
    if e["status"] == "below_range":
        return (f"below the model's range (raw output {e['raw_value']:.4g} {e['unit']})")
    return value_text(e, conf)


def model_tag(e: dict) -> str:
    """"  [model]" after a component's value; nothing where no model predicts it."""
    return f"  [{e['model']}]" if e["model"] and e["status"] != "no_model" else ""


def header(result: dict) -> list[str]:
    """The first line(s): world, model, interval level; with a robot-aware model the robot
    and what the model took of it."""
    conf = f"{100 * result['confidence']:g} %"
    slam = slam_label(result.get("slam"))
    if not result.get("model_takes_robot"):
        return [f"{result['world']}: predicted {slam} localization error "
                f"(setting {result['setting']}, model {result['model_store']}, {conf} "
                "intervals)"]
    from slam_predict.cli.predict_robot import robot_text

    robot = result["robot"]
    return [f"{result['world']}: predicted {slam} localization error for robot "
            f"{robot['name']} ({robot['file']})",
            f"model {result['model_store']} (robot-aware: takes the robot into account), "
            f"{conf} intervals; robot inputs: {robot_text(result)}"]


def format_text(result: dict, components) -> str:
    """Human-readable lines: value, interval and model per component, then warnings."""
    conf = f"{100 * result['confidence']:g} %"
    lines = header(result)
    if "plan" in result:
        from slam_predict.cli.plan_checks import plan_line

        lines.append(plan_line(result["plan"]))
    for comp in components:
        e = result[comp]
        lines.append(f"  {comp:<10s} {LABELS[comp]:<27s} {entry_text(e, conf)}{model_tag(e)}")
    if result.get("model_takes_robot"):
        from slam_predict.cli.predict_robot import failure_text

        lines += failure_text(result.get("failure"))
    lines += fitted_lines(result.get("fitted_settings") or {})
    lines += [f"warning: {w}" for w in result["warnings"]]
    return "\n".join(lines)


def fitted_lines(fitted: dict[str, str]) -> list[str]:
    """One line per collection setting of the training runs fitted to the seed study."""
    return [f"fitted: the training runs' {key} was fitted to the seed study, not measured: "
            f"{how}" for key, how in fitted.items()]
