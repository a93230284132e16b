"""The campaign parts of the report: overview, per-building summary, one section per world."""
from __future__ import annotations

import collections
import math
from collections.abc import Sequence

from slam_predict.errors import InputError
from slam_predict.learn.card import DEFAULT_SLAM, SLAM_ALGORITHMS, slam_label
from slam_predict.report import html as H
from slam_predict.report.campaign import Campaign, Run, WorldRuns

OTHER_HASH_KEYS = ("slam_compute", "nav", "explore", "stop", "metric")


def _deg(value) -> float:
    try:
        return math.degrees(float(value))
    except (TypeError, ValueError):
        return math.nan


def _counts(values: Sequence) -> list[tuple[str, int]]:
    """(value, count) pairs, most frequent first; None shown as 'unknown'."""
    counter = collections.Counter("unknown" if v is None else str(v) for v in values)
    return counter.most_common()


def _sum(values) -> float:
    numbers = [float(v) for v in values if isinstance(v, (int, float)) and not isinstance(v, bool)]
    return sum(numbers) if numbers else math.nan


def _hours(seconds: float) -> str:
    if not math.isfinite(seconds):
        return H.MISSING
    return f"{seconds:.0f} s ({seconds / 3600:.2f} h)"


def overview(campaign: Campaign) -> str:
    """Worlds, runs, settings and code versions, stop reasons, simulated and wall time."""
    runs = campaign.runs
    per_world = [len(w.runs) for w in campaign.worlds.values() if w.runs]
    sim = _sum(r.value("sim_duration_s") for r in runs)
    wall = _sum(r.value("wall_time_s") for r in runs)
    def counted(key: str, unit: str = "") -> str:
        return "; ".join(f"{v} ({n}{unit})" for v, n in _counts([r.value(key) for r in runs]))

    pairs = [("campaign folder", str(campaign.root.resolve())),
             ("worlds", len(campaign.summary_rows())),
             ("complete runs", len(runs)),
             ("runs per world", f"{min(per_world)}–{max(per_world)}" if per_world else H.MISSING),
             ("settings files", counted("settings_file", " runs")),
             ("robots", "; ".join(f"{v} ({n} runs)" for v, n in
                                  _counts([robot_text(r.value("sensor")) for r in runs]))),
             ("SLAM back-ends", "; ".join(f"{v} ({n} runs)" for v, n in
                                          _counts([r.value("slam", "type") or "gmapping"
                                                   for r in runs]))),
             ("odometry error models", counted("odometry_model", " runs")),
             ("code versions", counted("code_version", " runs")),
             ("simulated time", _hours(sim)),
             ("wall-clock time", _hours(wall)),
             ("speed", f"{sim / wall:.1f}× real time" if wall and math.isfinite(sim / wall)
              else H.MISSING)]
    body = H.key_values(pairs) if runs else H.key_values(pairs[:3])
    body += "<h3>Configuration hashes</h3>" + hash_table(runs)
    body += "<h3>Why runs stopped</h3>" + stop_table(campaign)
    return H.section("Campaign overview", body + H.notes(campaign.notes), anchor="overview")


def hash_table(runs: Sequence[Run]) -> str:
    """Distinct sets of configuration hashes (run.json config_hashes) and their run counts."""
    keys = hash_keys(runs)
    combos: dict[tuple, list[str]] = collections.OrderedDict()
    for run in runs:
        hashes = run.value("config_hashes") or {}
        key = tuple(str(hashes.get(k, H.MISSING)) for k in keys)
        combos.setdefault(key, []).append(run.world)
    rows = [[*key, H.num_cell(len(worlds), 0), ", ".join(sorted(set(worlds)))]
            for key, worlds in combos.items()]
    if not rows:
        return "<p>No run records.</p>"
    note = ("" if len(rows) == 1 else "<p>More than one configuration: compare worlds only "
            "within the same configuration.</p>")
    return H.table([*keys, "runs", "worlds"], rows) + note


def hash_keys(runs: Sequence[Run]) -> list[str]:
    """The hash table's columns: sim, the SLAM back-ends whose parameters the runs hash
    (gmapping when none does), slam_compute when a run has it, nav, explore, stop, metric."""
    present = {k for run in runs for k in (run.value("config_hashes") or {})}
    slam = [k for k in SLAM_ALGORITHMS if k in present] or [DEFAULT_SLAM]
    return ["sim", *slam, *(k for k in OTHER_HASH_KEYS if k in present or k != "slam_compute")]


def stop_table(campaign: Campaign) -> str:
    """Stop reasons per world (columns) with counts."""
    reasons = sorted({str(r.value("stop_reason")) for r in campaign.runs})
    if not reasons:
        return "<p>No run records.</p>"
    rows = []
    for name, world in campaign.worlds.items():
        counts = collections.Counter(str(r.value("stop_reason")) for r in world.runs)
        if world.runs:
            rows.append([name, *[H.num_cell(counts.get(k, 0), 0) for k in reasons]])
    return H.table(["world", *reasons], rows)


SUMMARY_HEADER = ["world", "runs", "trans_mean [m]", "std of trans_mean over runs [m]",
                  "rot_mean [rad]", "rot_mean [deg]", "std of rot_mean over runs [rad]",
                  "std of rot_mean over runs [deg]", "path length [m]", "rotation [rad]",
                  "coverage", "sim time [s]"]
ONE_RUN = "n/a (1 run)"


def robot_text(sensor) -> str:
    """A run's robot from its run.json ``sensor``: the laser (range, fov, beams) and the
    odometry error model and bounds, in a robot file's units; '—' without one."""
    try:
        laser, odom = sensor["laser"], sensor["odom"]
        x, y, yaw = odom["error"]
        return (f"laser {laser['range_max']:g} m, {math.degrees(laser['fov']):.0f}°, "
                f"{laser['samples']} beams; odometry {odom['model']} {x:g}, {y:g} m/m, "
                f"{math.degrees(yaw):.3g} °/rad")
    except (TypeError, KeyError, ValueError):
        return H.MISSING


def _spread(row: dict, key: str, digits: int, degrees: bool = False):
    """The std over runs of one component, or "n/a (1 run)" where one run has none."""
    if row.get("runs") == 1:
        return ONE_RUN
    return H.num_cell(_deg(row[key]) if degrees else row[key], digits)


def summary_cells(row: dict) -> list:
    """One per-building row (means over runs; std over runs with ddof 0, n/a for one run)."""
    return [row["world"], H.num_cell(row["runs"], 0),
            H.num_cell(row["trans_mean"], 4), _spread(row, "trans_std", 4),
            H.num_cell(row["rot_mean"], 5), H.num_cell(_deg(row["rot_mean"]), 3),
            _spread(row, "rot_std", 5), _spread(row, "rot_std", 3, degrees=True),
            H.num_cell(row["path_length_mean"], 1), H.num_cell(row["rotation_mean"], 1),
            H.num_cell(row["coverage_mean"], 3), H.num_cell(row["sim_time_mean_s"], 0)]


def summary(campaign: Campaign) -> str:
    """The per-building table (as summary.csv): error components over runs."""
    text = ("<p>Per building, over its runs: mean and standard deviation (ddof 0) of each run's "
            "mean absolute relation error (Kümmerle metric), translation in m, rotation in rad "
            "and deg; path length and rotation of the ground-truth path; explored share of the "
            "reachable free area; simulated duration. The standard deviations here are the "
            "spread <em>over runs</em> (the model components trans_std and rot_std); the "
            "per-run tables below give each run's spread <em>over its relations</em>, another "
            "quantity. One run has no spread over runs: n/a.</p>")
    rows = [summary_cells(row) for row in campaign.summary_rows()]
    return H.section("Per-building summary", text + H.table(SUMMARY_HEADER, rows,
                                                              table_id="summary"),
                     anchor="summary")


RUN_HEADER = ["run", "seed", "stop reason", "sim [s]", "wall [s]", "distance [m]",
              "rotation [rad]", "coverage", "trans_mean [m]", "std over relations [m]",
              "rot_mean [rad]", "rot_mean [deg]", "std over relations [rad]", "relations", "map",
              "trajectories"]


def run_cells(run: Run) -> list:
    """One row of a world's per-run table."""
    return [run.run_id, str(run.value("seed") if run.value("seed") is not None else H.MISSING),
            str(run.value("stop_reason") or H.MISSING),
            H.num_cell(run.value("sim_duration_s"), 1), H.num_cell(run.value("wall_time_s"), 1),
            H.num_cell(run.value("distance_m"), 1), H.num_cell(run.value("rotation_rad"), 1),
            H.num_cell(run.value("coverage"), 3),
            H.num_cell(run.value("metric", "trans_mean"), 4),
            H.num_cell(run.value("metric", "trans_std"), 4),
            H.num_cell(run.value("metric", "rot_mean"), 5),
            H.num_cell(_deg(run.value("metric", "rot_mean")), 3),
            H.num_cell(run.value("metric", "rot_std"), 5),
            H.num_cell(run.value("metric", "n"), 0),
            "yes" if run.has_map else "no", "yes" if run.has_trajectories else "no"]


def _trans_error(run: Run) -> float:
    value = run.value("metric", "trans_mean")
    return float(value) if isinstance(value, (int, float)) else math.inf


def map_candidates(world: WorldRuns) -> list[Run]:
    """Runs with map and trajectories: the median-error run first, then by closeness to it."""
    usable = sorted((r for r in world.runs if r.has_map and r.has_trajectories),
                    key=lambda r: (_trans_error(r), r.run_id))
    middle = (len(usable) - 1) // 2
    order = sorted(range(len(usable)), key=lambda i: (abs(i - middle), i))
    return [usable[i] for i in order]


def _draw(world: WorldRuns, run: Run) -> tuple[bytes, float]:
    """(PNG of the run's map overlay, map resolution m/px); raises on unreadable files."""
    from slam_predict.collect.record import load_record
    from slam_predict.formats.mapserver import read_map
    from slam_predict.report.figures import map_overlay

    grid = read_map(run.folder / "map.yaml")
    _, traj = load_record(run.folder)
    if len(traj.t) == 0:
        raise InputError("empty trajectories", run.folder)
    title = (f"{world.name} / {run.run_id}: final SLAM map, trans_mean "
             f"{H.number(run.value('metric', 'trans_mean'), 3)} m")
    return map_overlay(grid, traj.ground_truth, traj.slam, title), grid.resolution


def map_figure(world: WorldRuns) -> tuple[str, list[str]]:
    """The map overlay of a representative run (HTML) and notes on what was missing."""
    notes: list[str] = []
    candidates = map_candidates(world)
    if not candidates:
        lacking = "no run keeps map.yaml and trajectories" if world.runs else "no run record"
        return "", [f"no map figure: {lacking} (e.g. a campaign committed with run.json only; "
                    "re-running a run with its seed reproduces them)"]
    for rank, run in enumerate(candidates):
        try:
            png, resolution = _draw(world, run)
        except (InputError, OSError, ValueError, KeyError) as exc:
            text = (exc.one_line() if isinstance(exc, InputError)
                    else f"{exc.__class__.__name__}: {exc}")
            notes.append(f"{run.run_id}: map or trajectories unreadable ({text})")
            continue
        why = ("the only run with map and trajectories" if len(candidates) == 1 else
               "the run with the median translational error" if rank == 0 else
               "the readable run closest to the median translational error")
        slam = slam_label(run.value("slam", "type"))
        caption = (f"{run.run_id} ({why}): final {slam} map ({resolution:g} m/px) with the "
                   "ground-truth path (green, moved into the map frame by the start poses) "
                   "and the SLAM estimate (red).")
        return H.image(png, f"SLAM map of {world.name} {run.run_id}", caption), notes
    return "", notes + ["no map figure: no readable map"]


def world_section(world: WorldRuns) -> str:
    """One world: map figure, per-run table, notes."""
    figure, notes = map_figure(world)
    body = figure
    if world.runs:
        robots = _counts([robot_text(r.value("sensor")) for r in world.runs])
        body += H.key_values([("robot", "; ".join(f"{v} ({n} runs)" for v, n in robots))])
        body += H.table(RUN_HEADER, [run_cells(r) for r in world.runs])
    without_map = [r.run_id for r in world.runs if not (r.has_map and r.has_trajectories)]
    if without_map and len(without_map) < len(world.runs):
        notes.append("without map or trajectories: " + ", ".join(without_map))
    return H.section(f"World {world.name}", body + H.notes(world.notes + notes),
                     anchor=f"world-{world.name}")
