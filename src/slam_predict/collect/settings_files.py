"""Files for the ROS path's nodes, which read configuration files rather than a settings tree:
a settings file's ``sim_overrides``, inline SLAM parameters, ``nav_overrides`` and
``explore_overrides`` written out
under ~/.cache/slam_predict/settings/, each named by the hash of its content."""
from __future__ import annotations

from pathlib import Path
from typing import Any

from slam_predict.collect.settings import merge_trees
from slam_predict.config import load_yaml


def merged_robot_file(settings_path: Path, tree: dict[str, Any]) -> Path:
    """A robot YAML with ``sim_overrides`` applied, for nodes that read one file (ROS path);
    written atomically under ~/.cache/slam_predict/settings/, named by its content hash."""
    import yaml

    robot = load_yaml(tree["robot"])
    robot["sim"] = merge_trees(robot.get("sim", {}) or {}, tree["sim_overrides"])
    text = f"# {tree['robot']} + sim_overrides of {settings_path}\n" + yaml.safe_dump(robot)
    return _cached_file("robot", text)


def slam_params_file(settings_path: Path, tree: dict[str, Any]) -> Path:
    """The SLAM node's parameter YAML for a settings tree: the ``slam.params`` file, or, for
    inline or default parameters, a file with them and ``type`` written like
    :func:`merged_robot_file`."""
    import yaml

    section = tree["slam"]
    if isinstance(section.get("params"), str):
        return Path(section["params"])
    values = {"type": section.get("type", "gmapping"), **(section.get("params") or {})}
    text = f"# slam parameters of {settings_path}\n" + yaml.safe_dump(values)
    return _cached_file("slam", text)


def merged_explore_file(settings_path: Path, tree: dict[str, Any]) -> Path:
    """The explore node's YAML with ``explore_overrides`` set, cached like
    :func:`merged_robot_file`."""
    return _merged_yaml(Path(tree["explore"]), tree["explore_overrides"],
                        f"explore_overrides of {settings_path}")


def _digest(text: str) -> str:
    """The 12 hex digits that name a cached file or folder by its content."""
    import hashlib

    return hashlib.sha256(text.encode()).hexdigest()[:12]


def _cached_file(prefix: str, text: str) -> Path:
    """``text`` written atomically under ~/.cache/slam_predict/settings/, named by its hash."""
    from slam_predict.atomic import write_text

    out = Path.home() / ".cache" / "slam_predict" / "settings" / f"{prefix}_{_digest(text)}.yaml"
    if not out.is_file():
        out.parent.mkdir(parents=True, exist_ok=True)
        write_text(out, text)
    return out


def merged_nav_folder(tree: dict[str, Any]) -> Path:
    """The navigation folder with ``nav_overrides`` set: move_base parameters in its
    move_base.yaml, TrajectoryPlannerROS parameters in its base_local_planner.yaml (loaded after
    move_base.yaml, so it would win) and local_costmap parameters in its local_costmap.yaml,
    for the ROS path's move_base launch (which loads the folder's files); under
    ~/.cache/slam_predict/settings/, named by content hash, the other files copied as they
    are."""
    import shutil
    import tempfile

    from slam_predict.collect.settings import OVERRIDABLE_NAV_SECTIONS
    from slam_predict.nav.config import NAV_FILES

    source = Path(tree["navigation"])
    overrides = tree["nav_overrides"]
    sections = {k: v for k, v in overrides.items() if k in OVERRIDABLE_NAV_SECTIONS}
    top = {k: v for k, v in overrides.items() if k not in sections}
    merged = {"move_base.yaml": _merged_yaml(source / "move_base.yaml", top, "nav_overrides")}
    by_file: dict[str, dict[str, Any]] = {}
    for key, value in sections.items():
        by_file.setdefault(OVERRIDABLE_NAV_SECTIONS[key], {})[key] = value
    for name, part in by_file.items():
        what = "planner" if name == "base_local_planner.yaml" else "costmap"
        merged[name] = _merged_yaml(source / name, part, f"nav_overrides' {what} sections")
    folder = merged["move_base.yaml"].parent / (
        "move_base_" + _digest("".join(p.read_text() for p in merged.values())))
    if not folder.is_dir():
        # a staging folder of this process's own: parallel jobs may build the same folder
        staging = Path(tempfile.mkdtemp(prefix=folder.name + ".", dir=folder.parent))
        for name in NAV_FILES:
            if name in merged:
                shutil.copyfile(merged[name], staging / name)
            elif (source / name).is_file():
                shutil.copyfile(source / name, staging / name)
        try:
            staging.rename(folder)
        except OSError:
            if not folder.is_dir():
                raise
            shutil.rmtree(staging, ignore_errors=True)   # another job made the same folder
    return folder


def _merged_yaml(path: Path, overrides: dict[str, Any], what: str) -> Path:
    """``path``'s mapping with ``overrides`` set (mappings merged one level deep), cached."""
    import yaml

    data = dict(load_yaml(path) or {}) if path.is_file() else {}
    for key, value in overrides.items():
        if isinstance(value, dict) and isinstance(data.get(key), dict):
            data[key] = {**data[key], **value}
        else:
            data[key] = value
    return _cached_file(path.stem, f"# {path} + {what}\n" + yaml.safe_dump(data))
