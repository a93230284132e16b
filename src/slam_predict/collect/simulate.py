"""Simulated explorations of one plan, for ``slam-predict predict PLAN --simulate N|auto``.

The plan is written into the output folder as a Stage world (``DIR/<name>.world`` and its PNG
bitmap, each atomically) and run by the collection batch (:mod:`slam_predict.collect.batch`),
so ``DIR`` is an ordinary campaign folder: run folders, summary.csv and campaign.json. The
campaign's identity (:func:`slam_predict.collect.campaign.identity`) is extended with
:func:`plan_identity`, so resuming with another plan, seed, settings or robot is refused.

:func:`measured` turns the runs' run.json records into the four components the models predict
(mean and std over runs of each run's mean relation error ε_t in m, ε_r in rad), each with its
confidence interval (:mod:`slam_predict.metric.intervals`; a t-interval's lower bound below 0
is reported as 0, since an error is never negative).
"""
from __future__ import annotations

import hashlib
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from slam_predict.collect.campaign import CAMPAIGN_JSON, CampaignMismatch, mismatch, read_campaign
from slam_predict.collect.campaign import HINT as RESUME_HINT
from slam_predict.metric.intervals import mean_interval, std_interval

CONFIDENCE = 0.95
# component → (per-run metric key, statistic over runs, unit)
COMPONENTS = {"trans_mean": ("trans_mean", mean_interval, "m"),
              "trans_std": ("trans_mean", std_interval, "m"),
              "rot_mean": ("rot_mean", mean_interval, "rad"),
              "rot_std": ("rot_mean", std_interval, "rad")}
HINT = " (use another --out folder)"


def world_files(world) -> tuple[str, bytes]:
    """The Stage world text and PNG bitmap bytes ``world`` is written as."""
    from slam_predict.world.stagefile.writer import bitmap_png, world_text

    return world_text(world, f"{world.name}.png"), bitmap_png(world)


def plan_identity(world) -> dict[str, str]:
    """What identifies the simulated plan: its name and the SHA-256 of its world and bitmap."""
    text, png = world_files(world)
    return {"name": world.name,
            "world_sha256": hashlib.sha256(text.encode("utf-8")).hexdigest(),
            "bitmap_sha256": hashlib.sha256(png).hexdigest()}


def check_resume(out: Path, current: dict[str, Any], force: bool = False) -> None:
    """CampaignMismatch when ``out`` holds a campaign of another plan, seed or settings (read
    only: run before the slow steps, so a refusal costs nothing). With ``force`` only another
    plan is refused: a folder simulates one plan, as ``collect --force`` never mixes worlds
    either; another seed or other settings are then continued (and kept in the history)."""
    path = Path(out) / CAMPAIGN_JSON
    if not path.is_file():
        return
    recorded = read_campaign(path)
    problem = mismatch(recorded, current)
    if problem is None:
        return
    same_plan = recorded.get("plan") == current.get("plan")
    if force and same_plan:
        return
    raise CampaignMismatch(problem + (RESUME_HINT if same_plan else HINT), path)


def write_plan_world(world, out: Path) -> Path:
    """``out/<name>.world`` and its bitmap (atomic writes; kept when already there)."""
    from slam_predict.atomic import write_bytes, write_text

    path = Path(out) / f"{world.name}.world"
    if not path.is_file() or not path.with_suffix(".png").is_file():
        text, png = world_files(world)
        write_bytes(path.with_suffix(".png"), png)
        write_text(path, text)
    return path


def per_run_values(records: Sequence[dict]) -> dict[str, list[float]]:
    """Each run's mean relation errors: ``trans_mean`` (m) and ``rot_mean`` (rad)."""
    return {key: [float(r["metric"][key]) for r in records] for key in ("trans_mean", "rot_mean")}


def measured(records: Sequence[dict], confidence: float = CONFIDENCE) -> dict[str, dict]:
    """The four components over ``records`` (run.json contents), each as ``{"status", "value",
    "low", "high", "unit", "method", "runs"}``: low/high None with a single run, and the stds
    then ``status`` "n/a" with value None (one run gives no spread over runs)."""
    if not records:
        raise ValueError("no run records")
    values = per_run_values(records)
    out = {}
    for component, (key, statistic, unit) in COMPONENTS.items():
        est = statistic(values[key], confidence)
        low = None if est.low is None else max(est.low, 0.0)  # an error is never negative
        out[component] = {"status": "ok", "value": est.value, "low": low, "high": est.high,
                          "unit": unit, "method": est.method, "runs": est.n}
        if statistic is std_interval and est.n < 2:      # one run has no spread to measure
            out[component].update(status="n/a", value=None)
    return out


def cap_note(records: Sequence[dict], max_runs: int) -> str | None:
    """A note when ``--simulate auto`` stopped at ``max_runs`` although the seed study's
    run-count rule asks for more runs; None otherwise."""
    from slam_predict.metric.sampling import run_count

    values = per_run_values(records)
    decision = run_count(values["trans_mean"], values["rot_mean"])
    if len(records) >= max_runs and decision.runs_required > len(records):
        return (f"stopped at --max-runs {max_runs}: the run-count rule (95 %, d_t 0.03 m, "
                f"d_r 0.002 rad) asks for {decision.runs_required} runs")
    return None
