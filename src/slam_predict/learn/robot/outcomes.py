"""How often a campaign's explorations failed, per robot configuration (issue #18).

The robot-aware models learn from runs that mapped at least ``min_coverage`` of the floor; a
run below it is an exploration that failed (in the robot campaign: lasers of 3.8–4.5 m whose
map stopped growing, so that the seed study's stopping rule ended the run, with errors of a
failed map, 1.5–14 m). Those runs carry no usable
error, but how often they happen is part of the answer for a robot like theirs:
:func:`exploration_outcomes` counts them per configuration, the model card keeps the counts
(``exploration``), and :func:`failure_warning` turns them into a line for ``predict --robot``.
"""
from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from typing import Any

from slam_predict.errors import InputError
from slam_predict.learn.card import DEFAULT_SLAM
from slam_predict.words import plural

NEAR_FACTOR = 1.25   # configurations within this factor of the robot's range are "near"


def exploration_outcomes(folders: Sequence[os.PathLike | str], min_coverage: float,
                         slam: str = DEFAULT_SLAM) -> dict[str, Any]:
    """{"min_coverage", "by_config": {config: {"range_m", "runs", "failed"}}} over every run
    record of SLAM algorithm ``slam`` in the campaign folders (range_m: the laser's range_max,
    m; failed: runs whose coverage is below ``min_coverage``)."""
    from slam_predict.learn.robot.records import design_entry, skip_reason, slam_records

    by_config: dict[str, dict[str, Any]] = {}
    for path, record in slam_records(folders, slam):
        try:
            range_m = float(record["sensor"]["laser"]["range_max"])
        except (KeyError, TypeError, ValueError):
            raise InputError("run record without a laser range_max", path) from None
        entry = by_config.setdefault(design_entry(record, path)[0],
                                     {"range_m": range_m, "runs": 0, "failed": 0})
        entry["runs"] += 1
        entry["failed"] += int(skip_reason(record, min_coverage, path) == "low coverage")
    return {"min_coverage": float(min_coverage), "by_config": dict(sorted(by_config.items()))}


def failure_warning(outcomes: Mapping[str, Any] | None, range_m: float,
                    factor: float = NEAR_FACTOR) -> str | None:
    """A line when runs of configurations whose laser range lies within ``factor`` of
    ``range_m`` (m) failed to explore; None when none did (or without outcomes)."""
    if not outcomes or not math.isfinite(range_m) or range_m <= 0:
        return None
    near = [e for e in outcomes["by_config"].values()
            if range_m / factor <= float(e["range_m"]) <= range_m * factor]
    failed = sum(int(e["failed"]) for e in near)
    if not failed:
        return None
    runs = sum(int(e["runs"]) for e in near)
    low = min(float(e["range_m"]) for e in near)
    high = max(float(e["range_m"]) for e in near)
    span = f"{low:.3g} m" if math.isclose(low, high) else f"{low:.3g}–{high:.3g} m"
    return (f"{failed} of {plural(runs, 'training run')} with lasers of {span} (near this "
            f"robot's {range_m:.3g} m) mapped less than {100 * outcomes['min_coverage']:g} % of "
            "the floor before their exploration stopped; the prediction describes explorations "
            "that succeed")
