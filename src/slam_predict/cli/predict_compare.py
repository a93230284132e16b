"""``slam-predict predict PLAN --compare A B``: two SLAM algorithms' predictions side by side.

Each algorithm's error comes from its own model (the one whose card says it was trained for it,
:mod:`slam_predict.learn.slam_choice`; robot-aware ones with ``--robot``); the plan's features
are computed once per feature configuration. Below the table, the call on the mean
translational error ε_t (:func:`slam_predict.learn.compare.decide`): the algorithm expected to
be more accurate here with the probability that its ε_t is the lower, "too close to call" when
neither reaches :data:`~slam_predict.learn.compare.CALL_PROBABILITY`, or "no call" when a model
gives no usable ε_t. ``--json`` prints one object: ``world``, ``plan``, ``compare`` (the two
names), ``decision`` and ``predictions`` (per algorithm, ``predict --json``'s entries).
"""
from __future__ import annotations

import argparse
import json
import math
from typing import Any

from slam_predict.cli.predict_format import fitted_lines, interval_text
from slam_predict.learn.card import slam_label
from slam_predict.learn.compare import decide

PER_PREDICTION = ("setting", "model_store", "model_takes_robot", "robot", "failure",
                  "confidence", "fitted_settings")


def predictions(world, models: dict, predict) -> dict[str, dict]:
    """{algorithm: its model's result}, the features computed once per feature version (the
    definition and the hash of the whole configuration) and sight-line configuration."""
    computed: dict[str, dict] = {}
    results = {}
    for slam, model in models.items():
        key = json.dumps([model.card["feature_version"], model.sightline_config],
                         sort_keys=True, default=str)
        results[slam] = predict(world, model, computed.get(key))
        computed[key] = results[slam]["features"]
    return results


def run(args: argparse.Namespace, world, models: dict, predict, components) -> int:
    """Print both predictions and the call (text or ``--json``); returns the exit code."""
    from slam_predict.cli.plan_checks import plan_used

    results = predictions(world, models, predict)
    first, second = results
    decision = decide(first, second, {s: r["trans_mean"] for s, r in results.items()},
                      {s: float(r["confidence"]) for s, r in results.items()})
    plan = plan_used(world, args)
    if args.json:
        print(json.dumps(json_form(world.name, plan, results, decision, components), indent=2))
    else:
        print(text_form(world.name, plan, results, decision, components))
    return 0


def json_form(world: str, plan: dict, results: dict[str, dict], decision: dict,
              components) -> dict[str, Any]:
    """The ``--json`` object (module doc)."""
    out: dict[str, Any] = {"world": world, "plan": plan, "compare": list(results),
                           "decision": decision, "predictions": {}}
    for slam, result in results.items():
        entry = {"slam": slam, "model_takes_robot": False}
        entry.update({k: result[k] for k in PER_PREDICTION if k in result})
        entry.update({c: result[c] for c in components})
        entry.update({k: result[k] for k in ("free_space", "warnings", "features")})
        out["predictions"][slam] = entry
    return out


def cell(entry: dict) -> str:
    """One component of one algorithm: "0.222 m (0.070–0.390)", the rotation in rad and deg,
    or why there is no value."""
    if entry["status"] == "no_model":
        return "no model"
    if entry["status"] == "below_range":
        return "below the model's range"
    value = entry["value"]
    if entry["unit"] == "m":
        return f"{value:.3f} m " + (f"({interval_text(entry, 3)})" if entry["low"] is not None
                                    else "(no interval)")
    deg = f"{math.degrees(value):.2f}°"
    if entry["low"] is None:
        return f"{value:.4f} rad = {deg} (no interval)"
    bounds = {k: math.degrees(entry[k]) for k in ("low", "high")}
    return f"{value:.4f} rad ({interval_text(entry, 4)}) = {deg} ({interval_text(bounds, 2)})"


def model_text(slam: str, result: dict) -> str:
    """"gmapping: thesis-realistic (plan-only, setting realistic)"."""
    kind = "robot-aware" if result.get("model_takes_robot") else \
        f"plan-only, setting {result['setting']}"
    return f"{slam}: {result['model_store']} ({kind})"


def table(results: dict[str, dict], components) -> list[str]:
    """The side-by-side rows: a header with the algorithms, one row per component (and the
    failure probability of robot-aware models)."""
    names = list(results)
    rows = [["", *names]]
    for comp in components:
        rows.append([comp, *(cell(results[s][comp]) for s in names)])
    if any(results[s].get("failure") for s in names):
        rows.append(["P(exploration fails)", *(
            f"{100 * results[s]['failure']['probability']:.0f} %" if results[s].get("failure")
            else "no failure model" for s in names)])
    widths = [max(len(row[i]) for row in rows) for i in range(len(names) + 1)]
    return ["  " + "   ".join(text.ljust(w) for text, w in zip(row, widths, strict=True)).rstrip()
            for row in rows]


def decision_text(decision: dict, results: dict[str, dict]) -> list[str]:
    """The call in words (two lines: the call and the mean translational errors, then the
    probability and the rule)."""
    if decision["verdict"] == "no_call":
        return [f"no call on the mean translational error: {decision['reason']}"]
    prob = decision["probability"]
    lead = max(prob, key=prob.get)
    other = next(s for s in prob if s != lead)
    means = ", ".join(f"{s} {results[s]['trans_mean']['value']:.3f} m" for s in (lead, other))
    rule = (f"a call needs ≥ {decision['threshold']:g}; the two intervals taken as "
            "independent predictive distributions")
    if decision["verdict"] == "too_close_to_call":
        return [f"too close to call: mean translational error {means}",
                f"  probability {prob[lead]:.2f} that {lead}'s is the lower, {prob[other]:.2f} "
                f"{other}'s ({rule})"]
    return [f"expected to be more accurate here: {slam_label(lead)} (mean translational error "
            f"{means})",
            f"  probability {prob[lead]:.2f} that {lead}'s is the lower ({rule})"]


def text_form(world: str, plan: dict, results: dict[str, dict], decision: dict,
              components) -> str:
    """The human-readable lines (module doc)."""
    from slam_predict.cli.plan_checks import plan_line

    levels = sorted({f"{100 * r['confidence']:g} %" for r in results.values()})
    names = " and ".join(slam_label(s) for s in results)
    lines = [f"{world}: predicted localization error of {names} ({', '.join(levels)} "
             "intervals)", plan_line(plan),
             "models: " + "; ".join(model_text(s, r) for s, r in results.items())]
    robot_aware = [r for r in results.values() if r.get("model_takes_robot")]
    if robot_aware:
        from slam_predict.cli.predict_robot import robot_text

        robot = robot_aware[0]["robot"]
        texts = {s: robot_text({**r, "slam": s}) for s, r in results.items()
                 if r.get("model_takes_robot")}
        inputs = (next(iter(texts.values())) if len(set(texts.values())) == 1 else
                  "; ".join(f"{slam_label(s)}: {text}" for s, text in texts.items()))
        lines.append(f"robot {robot['name']} ({robot['file']}); robot inputs: {inputs}")
    lines += table(results, components)
    lines += decision_text(decision, results)
    lines += [f"{slam_label(s)}'s model: {line}" for s, r in results.items()
              for line in fitted_lines(r.get("fitted_settings") or {})]
    lines += [f"warning: {s}: {w}" for s, r in results.items() for w in r["warnings"]]
    return "\n".join(lines)
