"""Fidelity to the seed study: our per-building errors against the thesis' measured ones.

For each campaign (a ``slam-predict collect`` folder), the buildings it shares with the thesis
table (``stats_realistic.csv``: ``dataset``, ``transError.mean.mean`` m, ``rotError.mean.mean``
rad, ``totalLen`` m) are compared: Spearman rank correlation and median ratio ours/theirs of the
mean translational error, the mean rotational error and the explored path length, plus the
size trend (Spearman of our ε_t ratio with the building's free area, m²) and the acceptance bars
of issue #16 (:data:`ACCEPTANCE`), each with a bootstrap interval (:func:`bootstrap_intervals`),
and the run-to-run scatter (ours the sample std over a building's runs, theirs
``transError.mean.std`` / ``rotError.mean.std``).
"""
from __future__ import annotations

import csv
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from slam_predict.collect.record import with_metric
from slam_predict.collect.store import RunStore
from slam_predict.errors import InputError
from slam_predict.metric.runs import MIN_COVERAGE, sample_std

THESIS_COLUMNS = {"trans_mean": "transError.mean.mean", "rot_mean": "rotError.mean.mean",
                  "path_length_mean": "totalLen"}
# Run-to-run scatter: the std over a building's runs of the per-run mean error (theirs over
# ≥ 10 runs; ours the sample std, n − 1, over ≥ 2 runs).
SCATTER_COLUMNS = {"trans_std": "transError.mean.std", "rot_std": "rotError.mean.std"}
SCATTER_OF = {"trans_std": "trans_mean", "rot_std": "rot_mean"}


@dataclass(frozen=True)
class Bar:
    """One acceptance bar: ``figure`` of a comparison must lie in [low, high]."""

    label: str
    figure: str          # "spearman:<key>", "ratio:<key>", "extreme:<key>" or "size_trend"
    low: float
    high: float

    def value(self, comparison: Comparison) -> float:
        kind, _, key = self.figure.partition(":")
        if kind == "spearman":
            return comparison.spearman(key)
        if kind == "ratio":
            return comparison.median_ratio(key)
        if kind == "extreme":
            return comparison.extreme_ratio(key)
        return comparison.size_trend()

    def holds(self, comparison: Comparison) -> bool:
        value = self.value(comparison)
        return bool(np.isfinite(value) and self.low <= value <= self.high)


# The ε_t ratio must not follow the building's size (a bar of both bar sets).
NO_SIZE_TREND = Bar("no size trend: Spearman(ε_t ratio, free area) in [-0.3, 0.3]", "size_trend",
                    -0.3, 0.3)

# Issue #16's bars, ours vs the seed study's per-building means.
ACCEPTANCE = (
    Bar("ε_t Spearman ≥ 0.85", "spearman:trans_mean", 0.85, 1.0),
    Bar("ε_t median ratio in [0.85, 1.2]", "ratio:trans_mean", 0.85, 1.2),
    Bar("ε_r median ratio in [0.7, 1.4]", "ratio:rot_mean", 0.7, 1.4),
    Bar("path length median ratio in [0.85, 1.2]", "ratio:path_length_mean", 0.85, 1.2),
    NO_SIZE_TREND,
)


@dataclass
class Comparison:
    """One campaign against the thesis table."""

    name: str
    rows: list[dict[str, float]] = field(default_factory=list)   # per shared building
    per_run: dict[str, dict[str, np.ndarray]] = field(default_factory=dict)  # world → key → runs

    def values(self, key: str, side: str) -> np.ndarray:
        """Our (side 'ours') or the thesis' (side 'theirs') values of ``key``, by building."""
        return np.array([row[f"{key}_{side}"] for row in self.rows], dtype=float)

    def spearman(self, key: str) -> float:
        """Spearman rank correlation of ours vs theirs (nan under 3 buildings)."""
        from scipy.stats import spearmanr

        if len(self.rows) < 3:
            return float("nan")
        return float(spearmanr(self.values(key, "ours"), self.values(key, "theirs"))[0])

    def median_ratio(self, key: str) -> float:
        """Median over buildings of ours / theirs (buildings where it is undefined, e.g. a
        scatter of one run, left out; nan when none is left)."""
        if not self.rows:
            return float("nan")
        ratios = self.values(key, "ours") / self.values(key, "theirs")
        ratios = ratios[np.isfinite(ratios)]
        return float(np.median(ratios)) if len(ratios) else float("nan")

    def ratios(self, key: str) -> np.ndarray:
        """Per-building ours / theirs of ``key``."""
        return self.values(key, "ours") / self.values(key, "theirs")

    def extreme_ratio(self, key: str) -> float:
        """The per-building ours / theirs of ``key`` farthest from 1 on a log scale (nan when
        no building has one)."""
        ratios = self.ratios(key) if self.rows else np.array([])
        ratios = ratios[np.isfinite(ratios) & (ratios > 0)]
        return float(ratios[np.argmax(np.abs(np.log(ratios)))]) if len(ratios) else float("nan")

    def size_trend(self) -> float:
        """Spearman rank correlation of the ε_t ratio with the free area (nan under 3 buildings
        or without areas): near 0 when our error tracks theirs at every building size."""
        from scipy.stats import spearmanr

        areas = np.array([row.get("free_area_m2", np.nan) for row in self.rows], dtype=float)
        if len(self.rows) < 3 or not np.all(np.isfinite(areas)):
            return float("nan")
        return float(spearmanr(self.ratios("trans_mean"), areas)[0])

    @property
    def runs(self) -> int:
        return int(sum(row["runs"] for row in self.rows))


def read_thesis_table(path: Path) -> dict[str, dict[str, float]]:
    """The thesis stats table by building name; InputError when unreadable or incomplete."""
    path = Path(path)
    try:
        with open(path, newline="", encoding="utf-8") as handle:
            rows = list(csv.DictReader(handle, skipinitialspace=True))
    except OSError as exc:
        raise InputError(f"cannot read the thesis table: {exc.strerror}", path) from None
    columns = {**THESIS_COLUMNS, **SCATTER_COLUMNS}
    needed = ("dataset", *columns.values())
    if not rows or any(column not in rows[0] for column in needed):
        raise InputError(f"not a thesis stats table (needs columns {', '.join(needed)})", path)
    return {row["dataset"].strip(): {key: float(row[col]) for key, col in columns.items()}
            for row in rows}


def compare_campaign(folder: Path, thesis: dict[str, dict[str, float]],
                     min_runs: int = 1, name: str | None = None,
                     min_coverage: float = MIN_COVERAGE) -> Comparison:
    """Compare the buildings of campaign ``folder`` that the thesis table also holds; runs
    whose coverage (explored share of the reachable free area) is below ``min_coverage`` are
    left out (0: every run counts; default the failed-exploration rule ``MIN_COVERAGE``)."""
    folder = Path(folder)
    if not folder.is_dir():
        raise InputError("campaign folder not found", folder)
    store = RunStore(folder)
    comparison = Comparison(name or folder.name)
    for world in store.worlds():
        if world not in thesis:
            continue
        records = [r for r in with_metric(store.records(world))
                   if float(r.get("coverage", 1.0)) >= min_coverage]
        if len(records) < min_runs or not records:
            continue
        runs = comparison.per_run[world] = _per_run(records)
        row = {"world": world, "runs": len(records), "free_area_m2": _free_area(records),
               **our_figures(runs)}
        for key in (*THESIS_COLUMNS, *SCATTER_OF):
            row[f"{key}_theirs"] = thesis[world][key]
        comparison.rows.append(row)
    return comparison


def _per_run(records: list[dict]) -> dict[str, np.ndarray]:
    """Each run's value of the compared figures."""
    return {"trans_mean": np.array([r["metric"]["trans_mean"] for r in records], float),
            "rot_mean": np.array([r["metric"]["rot_mean"] for r in records], float),
            "path_length_mean": np.array([r["distance_m"] for r in records], float)}


def our_figures(runs: dict[str, np.ndarray]) -> dict[str, float]:
    """Our per-building figures from its runs' values (:func:`_per_run`): the means (as the
    campaign summary's ``building_row``) and the sample stds of the scatter columns."""
    figures = {f"{key}_ours": float(np.mean(runs[key])) for key in THESIS_COLUMNS}
    figures.update({f"{key}_ours": sample_std(runs[of]) for key, of in SCATTER_OF.items()})
    return figures


def _free_area(records: list[dict]) -> float:
    """The building's free area (m²) as its run records state it (nan when none does)."""
    areas = [float(r["free_area_m2"]) for r in records if r.get("free_area_m2") is not None]
    return float(np.mean(areas)) if areas else float("nan")


def acceptance_lines(comparison: Comparison, draws: int = 2000, seed: int = 0,
                     bars: Sequence[Bar] = ACCEPTANCE) -> list[str]:
    """One line per bar of ``bars``: the figure, its 95 % bootstrap interval
    (:func:`bootstrap_intervals`) and whether the figure holds the bar."""
    intervals = bootstrap_intervals(comparison, bars, draws, seed)
    lines = []
    for bar in bars:
        verdict = "pass" if bar.holds(comparison) else "FAIL"
        low, high = intervals[bar.label]
        lines.append(f"- {bar.label}: {bar.value(comparison):.2f} "
                     f"[95 % {low:.2f}, {high:.2f}] ({verdict})")
    return lines


def markdown_report(comparisons: list[Comparison], thesis_source: str) -> str:
    """docs/fidelity.md text: one summary row per campaign, then each campaign's buildings."""
    lines = ["| campaign | buildings | runs | Spearman ε_t | median ratio ε_t | Spearman ε_r "
             "| median ratio ε_r | median ratio path length | median ratio ε_t std "
             "| median ratio ε_r std |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for c in comparisons:
        lines.append(f"| {c.name} | {len(c.rows)} | {c.runs} | {c.spearman('trans_mean'):.2f} | "
                     f"{c.median_ratio('trans_mean'):.2f} | {c.spearman('rot_mean'):.2f} | "
                     f"{c.median_ratio('rot_mean'):.2f} | "
                     f"{c.median_ratio('path_length_mean'):.2f} | "
                     f"{c.median_ratio('trans_std'):.2f} | {c.median_ratio('rot_std'):.2f} |")
    lines += ["", f"Theirs: `transError.mean.mean` (m), `rotError.mean.mean` (rad) and `totalLen` "
              f"(m) of {thesis_source}. Ours: the campaign's per-building mean over runs. The std "
              f"columns compare the run-to-run scatter of the per-run mean errors "
              f"(`transError.mean.std`, `rotError.mean.std`; ours the sample std over a "
              f"building's runs, buildings with ≥ 2 runs)."]
    for c in comparisons:
        lines += ["", f"### {c.name}", "", f"Issue #16's bars ({len(c.rows)} buildings, "
                  f"{c.runs} runs; in brackets a 95 % bootstrap interval over buildings and "
                  "their runs):", "", *acceptance_lines(c), "",
                  "| building | free area (m²) | runs | ε_t ours (m) | ε_t theirs (m) | ratio "
                  "| ε_r ours (rad) | ε_r theirs (rad) | ratio | path ours (m) | path theirs (m) |",
                  "|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in sorted(c.rows, key=lambda row: row["trans_mean_theirs"]):
            lines.append(
                f"| {r['world']} | {r['free_area_m2']:.0f} | {r['runs']} "
                f"| {r['trans_mean_ours']:.3f} | "
                f"{r['trans_mean_theirs']:.3f} "
                f"| {r['trans_mean_ours'] / r['trans_mean_theirs']:.2f} "
                f"| {r['rot_mean_ours']:.4f} | {r['rot_mean_theirs']:.4f} | "
                f"{r['rot_mean_ours'] / r['rot_mean_theirs']:.2f} "
                f"| {r['path_length_mean_ours']:.0f} "
                f"| {r['path_length_mean_theirs']:.0f} |")
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------------------ bootstrap
# How sure a figure is: a campaign holds a few runs per building and a few dozen buildings, so
# a bar's figure moves with the runs that happened to be drawn and the buildings that happened
# to be chosen. Each bootstrap draw resamples the buildings with replacement and, within each
# drawn building, its runs with replacement, recomputes our per-building means and stds (the
# seed study's stay fixed: they average ≥ 10 runs each) and then the figure. With one run per
# building the interval reflects the choice of buildings only and is too narrow.


def resampled(comparison: Comparison, rng: np.random.Generator) -> Comparison:
    """One bootstrap replicate: buildings drawn with replacement, each with its runs drawn with
    replacement and our means recomputed."""
    rows = []
    for i in rng.integers(0, len(comparison.rows), len(comparison.rows)):
        row = dict(comparison.rows[i])
        runs = comparison.per_run.get(row["world"])
        if runs is not None:
            count = len(runs["trans_mean"])
            pick = rng.integers(0, count, count)
            row.update(our_figures({key: values[pick] for key, values in runs.items()}))
        rows.append(row)
    return Comparison(comparison.name, rows, comparison.per_run)


def bootstrap_intervals(comparison: Comparison, bars: Sequence[Bar], draws: int = 2000,
                        seed: int = 0, level: float = 0.95) -> dict[str, tuple[float, float]]:
    """Bar label → (low, high) central ``level`` interval of its figure over ``draws``
    bootstrap replicates (nan, nan when fewer than 3 buildings or no finite draw)."""
    if len(comparison.rows) < 3 or draws < 1:
        return {bar.label: (float("nan"), float("nan")) for bar in bars}
    rng = np.random.default_rng(seed)
    values = {bar.label: [] for bar in bars}
    with warnings.catch_warnings():   # a replicate may repeat one building: ρ undefined (nan,
        warnings.simplefilter("ignore", RuntimeWarning)   # scipy's ConstantInputWarning)
        for _ in range(draws):
            replicate = resampled(comparison, rng)
            for bar in bars:
                values[bar.label].append(bar.value(replicate))
    tail = (1.0 - level) / 2.0
    out = {}
    for bar in bars:
        finite = np.array(values[bar.label], float)
        finite = finite[np.isfinite(finite)]
        out[bar.label] = ((float("nan"), float("nan")) if len(finite) == 0 else
                          (float(np.quantile(finite, tail)), float(np.quantile(finite, 1 - tail))))
    return out
