"""Settings of a collection run, loaded from ``config/collect.yaml`` and the files it names."""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, Optional

from slam_predict.collect.stopping import StopConfig
from slam_predict.config import config_hash, from_dict, load_config, load_yaml, to_dict

DEFAULT_SETTINGS = Path(__file__).resolve().parents[3] / "config" / "collect.yaml"


@dataclass
class MetricSettings:
    """Relations sampling of the per-run metric (m, rad)."""

    pilot: int = 500
    margin_trans: float = 0.02
    margin_rot: float = 0.002
    confidence: float = 0.99


@dataclass
class CollectFiles:
    """The collect.yaml file itself: references to the component configs + inline sections."""

    robot: str = "robot.yaml"
    gmapping: str = "gmapping.yaml"
    navigation: str = "."
    explore: str = "explore.yaml"
    stop: StopConfig = field(default_factory=StopConfig)
    metric: MetricSettings = field(default_factory=MetricSettings)
    bag: bool = False


@dataclass
class CollectSettings:
    """Everything one run needs besides the world and the seed."""

    sim: Any
    gmapping: Any
    nav: Any
    explore: Any
    stop: StopConfig
    metric: MetricSettings
    bag: bool
    source: str

    def hashes(self) -> Dict[str, str]:
        """Short hashes of each component config, for run metadata."""
        return {name: config_hash(getattr(self, name))
                for name in ("sim", "gmapping", "nav", "explore", "stop", "metric")}


def load_settings(path: Optional[os.PathLike | str] = None) -> CollectSettings:
    """Load collect.yaml (default: the package's config/collect.yaml) and the files it names."""
    from slam_predict.explore.explorer import ExploreConfig
    from slam_predict.nav.config import load_nav_config
    from slam_predict.sim import SimConfig
    from slam_predict.slam.gmapping.params import load_params

    path = Path(path or DEFAULT_SETTINGS)
    files = from_dict(CollectFiles, load_yaml(path), str(path))
    base = path.parent
    return CollectSettings(
        sim=load_config(SimConfig, base / files.robot, "sim"),
        gmapping=load_params(base / files.gmapping),
        nav=load_nav_config(base / files.navigation),
        explore=load_config(ExploreConfig, base / files.explore),
        stop=files.stop, metric=files.metric, bag=files.bag, source=str(path))


def settings_dict(settings: CollectSettings) -> Dict[str, Any]:
    """Plain-dict form of every component config (recorded beside run.json)."""
    return {name: to_dict(getattr(settings, name))
            for name in ("sim", "gmapping", "nav", "explore", "stop", "metric")}
