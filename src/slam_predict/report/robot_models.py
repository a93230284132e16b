"""The report's section for a robot-aware model folder (card ``kind: robots``, issue #18).

Instead of the plan-only card's table and predictions: what the models were trained on (plan
features, the robot inputs with their units and training ranges, the SLAM range cap, the
design), the evaluation figures of every model under every protocol, and partial-dependence
plots — per component, the model's prediction averaged over the training points (buildings ×
configurations) as one robot input sweeps its range
(:meth:`~slam_predict.learn.robot.predict.RobotModel.partial_dependence`), the training range
shaded, the design's configurations as ticks, and the failure probability's evaluation.
Predictions for the campaign's runs, each from its recorded robot:
:mod:`slam_predict.report.robot_predictions`.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from slam_predict.learn.card import PROTOCOLS, card_slam, fitted_summary, range_cap_name
from slam_predict.learn.dataset import COMPONENTS, UNITS
from slam_predict.learn.robot.inputs import ALL_ROBOT_INPUTS, ROBOT_UNITS
from slam_predict.report import html as H
from slam_predict.report.labels import LABELS

PROTOCOL_LABELS = {"buildings": "held-out buildings", "configs": "held-out configurations",
                   "both": "held-out buildings × configurations"}
GRID_POINTS = 25
WIDEN = 0.1    # the plots reach 10 % of the training span beyond it (not past 0 or maxUrange)


def _range_text(values) -> str:
    low, high = values
    return f"{low:.4g} – {high:.4g}"


def overview(card: dict[str, Any]) -> str:
    """Key facts of a robot-aware card and its inputs' ranges."""
    design = card.get("design") or {}
    cap = card.get("max_urange_m")
    cap_name = range_cap_name(card_slam(card))
    pairs = [("description", card.get("description", "") or H.MISSING),
             ("kind", "robot-aware: plan features + the robot as inputs"),
             ("feature version", card.get("feature_version", H.MISSING)),
             (cap_name, f"{cap:g} m (range input = min(laser range, {cap_name}))"
              if cap is not None else "unset (range input = laser range)"),
             ("training", f"{len(card.get('training_buildings', []))} buildings, "
                          f"{len(design.get('configs', {}))} robot configurations, "
                          f"{design.get('points', H.MISSING)} points, "
                          f"{design.get('runs', H.MISSING)} runs"),
             ("interval confidence", card.get("confidence", H.MISSING)),
             ("fitted collection settings", fitted_summary(card)),
             ("created", card.get("created", H.MISSING)),
             ("libraries", ", ".join(f"{k} {v}" for k, v in card.get("versions", {}).items())
              or H.MISSING)]
    return H.key_values(pairs) + ranges_table(card)


def ranges_table(card: dict[str, Any]) -> str:
    """Every input: kind, unit, the model's range (warnings outside it) and the design's."""
    bounds = (card.get("design") or {}).get("bounds") or {}
    rows = []
    for name, span in card.get("input_ranges", {}).items():
        robot = name in ALL_ROBOT_INPUTS
        rows.append([name, "robot" if robot else "plan", ROBOT_UNITS.get(name, ""),
                     H.Cell(_range_text(span), numeric=True),
                     H.Cell(_range_text(bounds[name]), numeric=True) if name in bounds
                     else H.MISSING])
    return H.table(["input", "kind", "unit", "training range", "design bounds"], rows)


METRIC_HEADER = ["component", "unit", "model", "protocol", "test points", "median % error",
                 "R²", "coverage", "median interval width", "monotone in the robot"]


def _monotone_text(entry: dict) -> str:
    """"yes", "no (worst drop …)" from a model's monotone check, "—" without one."""
    check = (entry or {}).get("monotone")
    if not isinstance(check, dict):
        return H.MISSING
    if check.get("passed"):
        return "yes"
    drops = check.get("worst_drop") or {}
    name, drop = max(drops.items(), key=lambda kv: kv[1], default=("?", math.nan))
    return f"no ({name} −{100 * drop:.0f} %)"


def metrics_table(card: dict[str, Any]) -> str:
    """Every model of every component under every evaluation protocol; best in bold."""
    rows, classes = [], []
    for component in COMPONENTS:
        comp = (card.get("components") or {}).get(component)
        if not isinstance(comp, dict):
            continue
        for kind, entry in comp.get("models", {}).items():
            metrics = (entry or {}).get("metrics") or {}
            for protocol in [p for p in PROTOCOLS if p in metrics] or [None]:
                m = metrics.get(protocol, {}) if protocol else {}
                pct = m.get("median_pct_error")
                rows.append([component, UNITS[component], kind,
                             PROTOCOL_LABELS.get(protocol, H.MISSING),
                             H.num_cell(m.get("n_points"), 0),
                             H.num_cell(100 * pct if isinstance(pct, (int, float)) else None, 1),
                             H.num_cell(m.get("r2"), 3), H.num_cell(m.get("coverage"), 3),
                             H.num_cell(m.get("width_median"), 4), _monotone_text(entry)])
                classes.append("best" if kind == comp.get("best") else "")
    return H.table(METRIC_HEADER, rows, row_classes=classes)


def _span(model, name: str) -> tuple[float, float]:
    """The plotted range of a robot input: its training range widened by WIDEN each side,
    not below 0 (every robot input is ≥ 0) nor, for the range, beyond maxUrange."""
    low, high = model.card["input_ranges"][name]
    width = (high - low) or abs(high) or 1.0
    low, high = max(0.0, low - WIDEN * width), high + WIDEN * width
    cap = model.max_urange_m
    if name == "laser_range_max_m" and cap is not None:
        high = min(high, cap)
    return low, high


def curves(model, component: str) -> dict[str, dict]:
    """The partial-dependence curves of ``component`` against every robot input the training
    runs varied (the resolution of runs collected at one is left out)."""
    out = {}
    for j, name in enumerate(model.names):
        low, high = model.card["input_ranges"].get(name, (0.0, 0.0))
        if name not in ALL_ROBOT_INPUTS or low == high:
            continue
        grid, values = model.partial_dependence(component, name, GRID_POINTS, _span(model, name))
        cap = model.max_urange_m if name == "laser_range_max_m" else None
        out[name] = {"grid": grid, "values": values, "trained": model.card["input_ranges"][name],
                     "configs": np.unique(model.points[:, j]),
                     "xlabel": f"{name} [{ROBOT_UNITS[name]}]", "cap": cap}
    return out


def pdp_section(entry) -> str:
    """Partial-dependence figures, one per component the model predicts."""
    from slam_predict.report.figures import partial_dependence

    model = entry.store
    figures = []
    for component in [c for c in COMPONENTS if c in model.models]:
        kind = model.card["components"][component]["best"]
        unit = UNITS[component]
        png = partial_dependence(curves(model, component),
                                 f"average predicted {component} [{unit}]",
                                 f"{entry.name}: {LABELS[component]} ({kind})")
        figures.append(H.image(png, f"partial dependence of {component}, model {entry.name}",
                               f"{LABELS[component]} ({unit}) predicted by {kind}, averaged "
                               "over the training points (buildings × configurations) with "
                               "one robot input set along its axis; shaded: the training "
                               "range; ticks: the design's configurations."))
    intro = ("<p>How the model's prediction depends on each robot input: partial dependence "
             "(Friedman 2001), the mean prediction over every training point with that input "
             "replaced. Outside the shaded range the model extrapolates.</p>")
    return H.section(f"Partial dependence on the robot ({entry.name})",
                     intro + "".join(figures), level=3)


def failure_html(card: dict[str, Any]) -> str:
    """The failure model's evaluation: Brier scores and the reliability table ('' without)."""
    failure = card.get("failure")
    if not isinstance(failure, dict) or not isinstance(failure.get("evaluation"), dict):
        return ""
    ev = failure["evaluation"]
    share = f"{100 * float(failure['coverage_threshold']):g} %"
    rows = [[f"{b['low']:g}–{b['high']:g}", H.num_cell(b["runs"], 0),
             H.num_cell(b["predicted"], 3), H.num_cell(b["observed"], 3)]
            for b in ev.get("reliability", [])]
    return (f"<p>Failure probability (an exploration maps less than {share} of the floor; "
            f"{H.esc(str(failure.get('model', '')))}; {failure['failed']} of "
            f"{failure['runs']} training runs failed). {H.esc(ev['protocol'].capitalize())}: "
            f"Brier score {ev['brier']:.3f}, against {ev['brier_base_rate']:.3f} for the "
            "training runs' failure rate. Reliability:</p>"
            + H.table(["predicted p", "runs", "mean predicted", "observed failures"], rows))


def robot_card_section(entry) -> str:
    """The section of a robot-aware model folder (module doc); problems become notes."""
    if entry.card is None:
        return H.section(f"Model {entry.name}", H.notes(entry.notes), level=3)
    notes = list(entry.notes)
    body = (overview(entry.card)
            + "<p>Evaluation on the training campaign, per protocol: test points never seen "
              "in training (buildings, robot configurations or both held out); median "
              "percentage error, R² and coverage of the "
              f"{_percent(entry.card.get('confidence'))} intervals on the test points; best "
              "model per component in bold. Errors in m (translation) and rad (rotation).</p>"
            + metrics_table(entry.card) + failure_html(entry.card))
    if entry.store is not None:
        body += pdp_section(entry)
    return H.section(f"Model {entry.name}", body + H.notes(notes), level=3,
                     anchor=f"model-{entry.name}")


def _percent(value) -> str:
    try:
        number = 100 * float(value)
    except (TypeError, ValueError):
        return "model's"
    return f"{number:g} %" if math.isfinite(number) else "model's"
