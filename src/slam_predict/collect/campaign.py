"""A campaign folder's identity, ``DATA/campaign.json``: the base seed and the configuration.

Written when a campaign starts (atomically), it holds the base seed, the settings file (path and
SHA-256 of its text), the resolved settings (every component config, defaults included) with
their short hashes, and the code version. A resume is compared with it before any run starts:
another ``--seed``, settings that resolve differently or (for ``predict --simulate``) another
plan (its ``plan`` entry) is refused (:class:`CampaignMismatch`,
naming the difference), so runs of two configurations never share one summary.csv.

``--force`` accepts such a resume: the new configuration becomes the campaign's and the old one is
appended to ``history`` with the differences, so the mix stays documented (each run.json also
carries its own config hashes). A different code version alone is logged, not refused.

Folders collected before campaign.json existed are adopted on their first resume: when every
run.json carries the seed that ``--seed`` gives its run and the config hashes of the current
settings, campaign.json is written from them; otherwise the resume is refused likewise. In a
robot-design campaign each run has its own robot, so its hashes are compared with those of the
settings with that run's robot (``run_hashes``).
"""
from __future__ import annotations

import datetime
import hashlib
import json
import logging
import math
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

from slam_predict.atomic import write_text
from slam_predict.collect.store import LOCK_FILE, RUN_JSON, RunStore, run_seed
from slam_predict.errors import InputError

LOG = logging.getLogger(__name__)
CAMPAIGN_JSON = "campaign.json"
SCHEMA_VERSION = 1
MAX_LISTED = 3  # differences named in an error line
HINT = " (use a new --out folder, or --force to continue with the new ones)"
RunHashes = Callable[[str, int], "dict[str, str] | None"]   # (world, run index) → config hashes


class CampaignMismatch(InputError):
    """A resume whose seed or settings differ from the campaign's (exit 2)."""


def identity(settings, base_seed: int, code_version: str) -> dict[str, Any]:
    """The campaign.json content describing a collection with ``settings`` and ``base_seed``."""
    from slam_predict.collect.settings import settings_dict
    from slam_predict.paths import portable_path

    return {"schema": SCHEMA_VERSION, "base_seed": int(base_seed),
            "settings_file": portable_path(settings.source),
            "settings_sha256": file_sha256(settings.source),
            "config_hashes": settings.hashes(), "settings": json_plain(settings_dict(settings)),
            "code_version": code_version}


def file_sha256(path: os.PathLike | str) -> str:
    """SHA-256 (hex) of a file's bytes."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def json_plain(value: Any) -> Any:
    """``value`` as it reads back from JSON (tuples → lists), so comparisons are like for like."""
    return json.loads(json.dumps(value))


UNITS = {"laser.range_max": "m", "laser.range_min": "m", "laser.noise_std": "m",
         "laser.rate_hz": "Hz", "robot.footprint_side": "m", "robot.max_vel_x": "m/s",
         "robot.max_vel_theta": "rad/s", "gmapping.maxRange": "m", "gmapping.maxUrange": "m"}


def differences(old: Any, new: Any, prefix: str = "") -> list[str]:
    """Key paths where two JSON-like trees differ, as ``'path: old -> new'``."""
    if isinstance(old, dict) and isinstance(new, dict):
        out: list[str] = []
        for key in sorted(set(old) | set(new), key=str):
            path = f"{prefix}.{key}" if prefix else str(key)
            if key not in old:
                out.append(f"{path}: (absent) -> {shown(path, new[key])}")
            elif key not in new:
                out.append(f"{path}: {shown(path, old[key])} -> (absent)")
            else:
                out.extend(differences(old[key], new[key], path))
        return out
    return [] if old == new else [f"{prefix}: {shown(prefix, old)} -> {shown(prefix, new)}"]


def shown(path: str, value: Any) -> str:
    """A settings value as a robot file writes it: the laser's fov in degrees, its mounting yaw
    and the odometry's yaw error in degrees (per radian), the robot file's other values with
    their unit (:data:`UNITS`); anything else as it is."""
    unit = next((u for key, u in UNITS.items() if path.endswith(key)), None)
    if unit and isinstance(value, (int, float)) and not isinstance(value, bool):
        return f"{value!r} {unit}"
    try:
        if path.endswith("laser.fov"):
            return f"{math.degrees(value):.6g} deg"
        if path.endswith(("laser.pose", "odom.error")) and len(value) == 3:
            unit = " deg]" if path.endswith("pose") else " deg/rad]"
            return f"[{value[0]!r}, {value[1]!r}, {math.degrees(value[2]):.6g}{unit}"
    except TypeError:
        pass
    return repr(value)


def describe(found: list[str]) -> str:
    """The first few differences on one line."""
    more = f" (and {len(found) - MAX_LISTED} more)" if len(found) > MAX_LISTED else ""
    return "; ".join(found[:MAX_LISTED]) + more


def mismatch(recorded: dict[str, Any], current: dict[str, Any]) -> str | None:
    """Why a resume with ``current`` does not continue the campaign ``recorded``, or None."""
    if recorded.get("base_seed") != current["base_seed"]:
        return (f"the campaign was collected with --seed {recorded.get('base_seed')}, "
                f"not --seed {current['base_seed']}")
    if recorded.get("plan") != current.get("plan"):
        return plan_mismatch(recorded.get("plan"), current.get("plan"))
    if recorded.get("design", {}).get("sha256") != current.get("design", {}).get("sha256"):
        return design_mismatch(recorded.get("design"), current.get("design"))
    if recorded.get("ros") != current.get("ros"):
        return ros_mismatch(recorded.get("ros"), current.get("ros"))
    found = differences(recorded.get("settings"), current["settings"])
    if found:   # the robot's own values (sim) before what follows from them (gmapping, nav)
        found.sort(key=lambda text: not text.startswith("sim."))
        return f"the settings differ from the campaign's: {describe(found)}"
    return None


def plan_mismatch(old: dict[str, Any] | None, new: dict[str, Any] | None) -> str:
    """Why a campaign of plan ``old`` (``predict --simulate``'s ``plan`` entry, None for a
    ``collect`` campaign) is not one of plan ``new``."""
    if old is None or new is None:
        kind = "'slam-predict collect'" if old is None else "'predict --simulate'"
        return f"the folder holds a {kind} campaign"
    if old.get("name") != new.get("name"):
        return f"the campaign simulated plan '{old.get('name')}', not '{new.get('name')}'"
    return (f"the campaign simulated another version of plan '{new.get('name')}' (its map or "
            "start pose differ)")


def ros_mismatch(old: dict[str, Any] | None, new: dict[str, Any] | None) -> str:
    """Why a campaign run by ``batch_explore`` with nodes and launch options ``old`` (its
    ``ros`` entry; None for an in-process campaign) is not one with ``new``."""
    if old is None or new is None:
        kind = "in-process ('slam-predict collect')" if old is None else "through the ROS graph"
        return f"the campaign was collected {kind}"
    return f"the campaign ran other nodes or launch options: {describe(differences(old, new))}"


def design_mismatch(old: dict[str, Any] | None, new: dict[str, Any] | None) -> str:
    """Why a campaign of robot design ``old`` (``collect --design``'s ``design`` entry, None
    without one) is not one of design ``new``."""
    if old is None:
        return "the campaign was collected without --design"
    if new is None:
        return f"the campaign was collected with --design {old.get('file')}"
    return f"the design file differs from the campaign's ({old.get('file')}, SHA-256 changed)"


def open_campaign(root: Path, current: dict[str, Any], force: bool = False,
                  run_hashes: RunHashes | None = None, hint: str = HINT) -> dict[str, Any]:
    """Check a (new, resumed or legacy) campaign folder against ``current`` and write
    campaign.json; raises :class:`CampaignMismatch` for a refused resume. ``run_hashes``: the
    config hashes each run of a legacy folder must carry (None: ``current``'s, the same for
    every run; None from it: the run is not one the campaign would collect). ``hint``: how the
    user asks for a new folder or forces the resume, appended to the refusal."""
    path = Path(root) / CAMPAIGN_JSON
    if not path.is_file():
        return _adopt(Path(root), current, force, run_hashes, hint)
    recorded = read_campaign(path)
    problem = mismatch(recorded, current)
    if problem is None:
        if recorded.get("code_version") != current["code_version"]:
            LOG.info("%s: collected with code %s, resumed with %s", path,
                     recorded.get("code_version"), current["code_version"])
        return recorded
    if not force:
        raise CampaignMismatch(problem + hint, path)
    LOG.warning("%s: %s; continuing (--force)", path, problem)
    history = recorded.pop("history", []) + [{**recorded, "replaced": _now(), "reason": problem}]
    return _write(path, {**current, "history": history})


def _adopt(root: Path, current: dict[str, Any], force: bool,
           run_hashes: RunHashes | None, hint: str) -> dict[str, Any]:
    """campaign.json for a new folder, or for one collected without it (before campaign.json
    existed, or on another machine: campaign.json is not committed)."""
    problem, where, runs = legacy_mismatch(RunStore(root), current, run_hashes)
    if problem and not force:
        raise CampaignMismatch(problem + hint, where)
    extra: dict[str, Any] = {"created": _now()}
    if runs:
        extra["adopted"] = {"runs": runs, **({"reason": problem} if problem else {})}
    if problem:
        LOG.warning("%s: %s; continuing (--force)", where, problem)
    return _write(root / CAMPAIGN_JSON, {**current, **extra})


def legacy_mismatch(store: RunStore, current: dict[str, Any],
                    run_hashes: RunHashes | None = None):
    """For a folder without campaign.json: (why its run records do not match ``current`` and
    ``run_hashes`` (see :func:`open_campaign`) or None, the run.json concerned, how many
    records there are)."""
    problem, where, count = None, None, 0
    for world in store.worlds() if store.root.is_dir() else []:
        for index in store.completed(world):
            run_json = store.run_dir(world, index) / RUN_JSON
            count += 1
            expected = (current["config_hashes"] if run_hashes is None
                        else run_hashes(world, index))
            found = record_mismatch(json.loads(run_json.read_text()), world, index, current,
                                    expected)
            if found and problem is None:
                problem, where = found, run_json
    return problem, where, count


def record_mismatch(record: dict[str, Any], world: str, index: int, current: dict[str, Any],
                    expected: dict[str, str] | None) -> str | None:
    """Why one run.json was not collected with ``current``'s seed and settings (config hashes
    ``expected``; None: a run the campaign would not collect), or None."""
    seed = record.get("seed")
    if seed is not None and int(seed) != run_seed(current["base_seed"], world, index):
        return f"collected with another base seed than --seed {current['base_seed']}"
    if expected is None:
        return f"run {index} of '{world}' is not a run of the campaign's design"
    hashes = record.get("config_hashes")
    if hashes is not None and hashes != expected:
        changed = sorted(k for k in set(hashes) | set(expected)
                         if hashes.get(k) != expected.get(k))
        return (f"collected with other settings than {current['settings_file']} "
                f"({', '.join(changed)} config{' differs' if len(changed) == 1 else 's differ'})")
    return None


def check_out_folder(root: Path) -> None:
    """InputError unless an existing ``root`` can be a campaign folder: not a file, writable,
    and, when not empty, holding a campaign (nothing else is touched). Whether a new folder
    can be created is the CLI's check (``cli.guards.check_creatable``)."""
    root = Path(root)
    if root.exists() and not root.is_dir():
        raise InputError("--out is a file, not a campaign folder", root)
    if root.is_dir():
        if not os.access(root, os.W_OK | os.X_OK):
            raise InputError("--out folder is not writable", root)
        if any(root.iterdir()) and not is_campaign(root):
            raise InputError("--out folder is not empty and holds no campaign (no campaign.json, "
                             "summary.csv or run folders)", root)


def is_campaign(root: Path) -> bool:
    """True when ``root`` holds campaign.json, summary.csv, run folders, their leftovers or a
    batch's lock file."""
    return ((root / CAMPAIGN_JSON).exists() or (root / "summary.csv").exists()
            or (root / LOCK_FILE).exists()
            or any(root.glob("*/run_[0-9][0-9][0-9]")) or any(root.glob("*/.run_*.tmp")))


def read_campaign(path: Path) -> dict[str, Any]:
    """campaign.json's content; InputError when unreadable."""
    try:
        data = json.loads(Path(path).read_text())
    except (OSError, ValueError) as exc:
        raise InputError(f"unreadable campaign record: {exc}", path) from None
    if not isinstance(data, dict):
        raise InputError("campaign record is not a JSON object", path)
    return data


def recorded_settings_file(root: os.PathLike | str) -> str | None:
    """The settings file the campaign in ``root`` records (campaign.json ``settings_file``), or
    None without a campaign.json or that entry; InputError when campaign.json is unreadable."""
    path = Path(root) / CAMPAIGN_JSON
    if not path.is_file():
        return None
    recorded = read_campaign(path).get("settings_file")
    return recorded if isinstance(recorded, str) and recorded else None


def _write(path: Path, content: dict[str, Any]) -> dict[str, Any]:
    write_text(path, json.dumps(content, indent=1, sort_keys=True) + "\n")
    return content


def _now() -> str:
    return datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds")
