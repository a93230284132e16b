"""A fidelity campaign judged in declared parts: buildings a setting was fitted on, and the rest.

A parts file (YAML) names the campaign's building subsets before the judged part is collected::

    declared: 2026-12-05, commit abc1234
    fitted: [slam_compute.rebuild_s_per_line_cell]   # the settings fitted on the 'fit' part
    parts:
      fit: [Borchen4_updated, ...]
      judge: [130604-Plan_updated, ...]

Each part is compared with the seed study on its own (:func:`part_comparison`) against the
chain's bars (:data:`CHAIN_BARS`: ε_t, ε_r and path median ratios, ε_t Spearman, the size trend
and the widest per-building ε_t and path ratio), and its run ends are checked
(:func:`run_ends`: no run ends with its robot stuck, every run covers ≥ :data:`FULL_COVERAGE` of the
reachable floor).
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

from slam_predict.collect.fidelity import NO_SIZE_TREND, Bar, Comparison, acceptance_lines
from slam_predict.collect.store import RunStore
from slam_predict.config import load_yaml
from slam_predict.errors import InputError

FULL_COVERAGE = 0.95   # share of the reachable free floor a complete exploration maps

# The collection chain's bars on buildings it was not fitted on (ours ÷ the seed study).
CHAIN_BARS = (
    Bar("ε_t median ratio in [0.9, 1.1]", "ratio:trans_mean", 0.9, 1.1),
    Bar("ε_t Spearman ≥ 0.9", "spearman:trans_mean", 0.9, 1.0),
    Bar("ε_r median ratio in [0.8, 1.25]", "ratio:rot_mean", 0.8, 1.25),
    Bar("path length median ratio in [0.85, 1.15]", "ratio:path_length_mean", 0.85, 1.15),
    NO_SIZE_TREND,
    Bar("widest building ε_t ratio in [0.6, 1.6]", "extreme:trans_mean", 0.6, 1.6),
    Bar("widest building path ratio in [0.6, 1.6]", "extreme:path_length_mean", 0.6, 1.6),
)


def load_parts(path: Path | str) -> dict[str, list[str]]:
    """Part name → building names of a parts file; InputError naming the file when it has no
    ``parts`` mapping of name lists or a building sits in two parts."""
    data = load_yaml(path)
    parts = data.get("parts")
    if not isinstance(parts, dict) or not parts:
        raise InputError("needs a 'parts' mapping of part name to building names", path)
    seen: dict[str, str] = {}
    for name, worlds in parts.items():
        if not isinstance(worlds, list) or not all(isinstance(w, str) for w in worlds):
            raise InputError(f"part '{name}' must be a list of building names", path)
        for world in worlds:
            if world in seen:
                raise InputError(f"building '{world}' is in parts '{seen[world]}' and "
                                 f"'{name}'", path)
            seen[world] = str(name)
    return {str(name): list(worlds) for name, worlds in parts.items()}


def part_comparison(comparison: Comparison, name: str, worlds: Sequence[str]) -> Comparison:
    """The buildings of ``comparison`` that are in ``worlds``, as a comparison of their own."""
    wanted = set(worlds)
    rows = [row for row in comparison.rows if row["world"] in wanted]
    per_run = {w: runs for w, runs in comparison.per_run.items() if w in wanted}
    return Comparison(f"{comparison.name}: {name}", rows, per_run)


def ended_stuck(record: Mapping) -> bool:
    """The run ended with its robot stuck: it stopped ``stuck`` (before 2026-12-05), or its
    record says ``stuck_at_end``, or, in records without that key (before 2026-12-06), that
    the robot was ``stuck`` at some time."""
    stuck = record.get("stuck") or {}
    return record.get("stop_reason") == "stuck" or bool(stuck.get("stuck_at_end",
                                                                  stuck.get("stuck")))


def got_out(record: Mapping) -> bool:
    """The robot was stuck for ``stuck_timeout_s`` at some time but not when the run ended
    (records since 2026-12-06 only)."""
    stuck = record.get("stuck") or {}
    return bool(stuck.get("stuck")) and stuck.get("stuck_at_end") is False


def run_ends(folders: Sequence[Path], worlds: Sequence[str]) -> dict[str, list[str]]:
    """Every finished run of ``worlds`` in the campaign ``folders`` that ended with its robot
    stuck (:func:`ended_stuck`), that was stuck for a while and got out (:func:`got_out`), or
    that ended below :data:`FULL_COVERAGE`, as 'world run k (reason, coverage c[, floor swept
    s])' lines by kind (the swept share, records since 2026-12-07: a run that swept its floor
    but whose drifted map lies beside the plan has a high one)."""
    out: dict[str, list[str]] = {"stuck": [], "stuck for a while, got out": [],
                                 "low coverage": []}
    wanted = set(worlds)
    for folder in folders:
        store = RunStore(folder)
        for world in store.worlds():
            if world not in wanted:
                continue
            for record in store.records(world):
                coverage = float(record.get("coverage", 1.0))
                swept = record.get("coverage_swept")
                line = (f"{world} run {record.get('run_index', '?')} "
                        f"({record.get('stop_reason')}, coverage {coverage:.3f}"
                        + ("" if swept is None else f", floor swept {swept:.3f}") + ")")
                if ended_stuck(record):
                    out["stuck"].append(line)
                if got_out(record):
                    out["stuck for a while, got out"].append(line)
                if coverage < FULL_COVERAGE:
                    out["low coverage"].append(line)
    return out


def part_lines(comparison: Comparison, parts: Mapping[str, Sequence[str]],
               folders: Sequence[Path], draws: int = 2000) -> list[str]:
    """Markdown: for each part, the chain's bars with 95 % bootstrap intervals and the runs
    that ended stuck or incomplete."""
    lines: list[str] = []
    for name, worlds in parts.items():
        part = part_comparison(comparison, name, worlds)
        missing = sorted(set(worlds) - {row["world"] for row in part.rows})
        lines += ["", f"#### Part '{name}': {len(part.rows)} of {len(worlds)} buildings, "
                  f"{part.runs} runs", ""]
        lines += acceptance_lines(part, draws, bars=CHAIN_BARS)
        ends = run_ends(folders, worlds)
        for kind, runs in ends.items():
            lines.append(f"- runs {kind}: {len(runs)}" + (f" ({'; '.join(runs)})" if runs
                                                          else ""))
        if missing:
            lines.append(f"- not collected yet (or no run kept): {', '.join(missing)}")
    return lines
