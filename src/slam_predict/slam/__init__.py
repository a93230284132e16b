"""SLAM back-ends behind one small interface, registered by name (the YAML ``type:`` field).

A back-end is fed, scan by scan, the robot's odometry pose and the laser ranges::

    slam = create("gmapping", params=..., laser=LaserGeometry(...), rng=np.random.default_rng(1))
    for odom_pose, ranges, t in stream:
        pose = slam.update(odom_pose, ranges, t)   # map-frame robot pose when processed, else None
    grid = slam.map()                               # OccupancyGrid
    slam.map_to_odom()                              # (x, y, yaw) of the odom frame in the map frame

Poses are (x m, y m, yaw rad) of the robot base; ranges in m, times in s. Everything callers
outside ``slam/`` need is on :class:`SlamBackend`; back-ends outside slam_predict are loaded by
:func:`load_plugins` (docs/architecture.md "Adding a SLAM back-end"). Offline runs over logs and
bags: :mod:`.runner`, :mod:`.scans`, :mod:`.bag_input`.
"""
from __future__ import annotations

import importlib
import os
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from slam_predict.config import AT_LEAST_ONE, NON_NEGATIVE, Range
from slam_predict.errors import InputError, did_you_mean


@dataclass
class LaserGeometry:
    """A planar laser: beam angles (rad, in the laser frame, increasing), its pose in the robot
    base frame (x m, y m, yaw rad) and the sensor's maximum range (m; NaN if unknown)."""

    angles: np.ndarray
    pose_in_base: tuple[float, float, float] = (0.0, 0.0, 0.0)
    range_max: float = float("nan")

    def __post_init__(self):
        self.angles = np.asarray(self.angles, dtype=float).reshape(-1)
        self.pose_in_base = tuple(float(v) for v in self.pose_in_base)

    @property
    def beams(self) -> int:
        """Number of beams."""
        return len(self.angles)


@dataclass
class OccupancyGrid:
    """A ROS-style occupancy grid: ``data`` (height, width) int8 with −1 unknown, 0 free, 100
    occupied; row 0 is the lowest y; ``origin`` (x, y) m is the world position of cell (0, 0) as
    the producer defines it; ``resolution`` m/cell. ``known``: cells (x0, y0, x1, y1),
    end-exclusive, outside which every cell is −1, when the producer knows such a box (None:
    it does not; the grid must not be changed in place outside it)."""

    data: np.ndarray
    resolution: float
    origin: tuple[float, float]
    known: tuple[int, int, int, int] | None = None

    @property
    def width(self) -> int:
        """Number of columns (cells along x)."""
        return int(self.data.shape[1])

    @property
    def height(self) -> int:
        """Number of rows (cells along y)."""
        return int(self.data.shape[0])


@dataclass
class SlamNodeParams:
    """A SLAM ROS node's own parameters, whatever the back-end (slam_gmapping's names and
    defaults; frames, s). GMapping's parameters extend them, as slam_gmapping's do."""

    throttle_scans: int = 1
    base_frame: str = "base_link"
    map_frame: str = "map"
    odom_frame: str = "odom"
    transform_publish_period: float = 0.05
    tf_delay: float | None = None          # None: = transform_publish_period
    RANGES: ClassVar[dict[str, Range]] = {"throttle_scans": AT_LEAST_ONE,
                                          "transform_publish_period": NON_NEGATIVE,
                                          "tf_delay": NON_NEGATIVE}

    @property
    def effective_tf_delay(self) -> float:
        """tf_delay, defaulting to transform_publish_period as slam_gmapping does (s)."""
        return self.transform_publish_period if self.tf_delay is None else self.tf_delay


class SlamBackend:
    """Interface of a SLAM back-end (see the module docstring).

    A back-end class is its own factory: ``cls(params=..., laser=..., rng=...)``. Its parameter
    object is built by :meth:`params_from_dict` (strict; an optional ``type:`` entry naming the
    back-end is accepted) and must carry ``map_update_interval`` (s, how often a ROS node or the
    closed loop republishes the map). What callers outside ``slam/`` need is here; nothing else
    of a back-end may be assumed.
    """

    name = "abstract"
    label = "abstract"        # human-readable name, e.g. "GMapping"
    params = None             # the parameter object the instance runs with
    # True: the ROS node republishes the map every map_update_interval s, scans processed or not
    # (slam_toolbox's map thread); False: only with a processed scan (slam_gmapping)
    map_thread = False

    # --- parameters (class level: callers build them before any instance exists)
    @classmethod
    def params_from_dict(cls, data, source: str = "<config>"):
        """The back-end's parameter object from a mapping (unknown keys rejected)."""
        raise NotImplementedError

    @classmethod
    def params_from_record(cls, data, source: str = "<run record>"):
        """The parameters a collected run recorded (run.json ``sensor_logs``), for its replay;
        default :meth:`params_from_dict`. A back-end whose new options change its behaviour
        maps a record that lacks them to the behaviour the run had."""
        return cls.params_from_dict(data, source)

    @classmethod
    def default_params(cls):
        """The back-end's default parameters."""
        return cls.params_from_dict({}, f"{cls.name} defaults")

    @classmethod
    def extent_of(cls, params) -> tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax) m of the largest map ``params`` let the back-end publish:
        the canvas of the stop rule's snapshots."""
        raise NotImplementedError

    @classmethod
    def warmup(cls) -> None:
        """Load (compile at worst) the back-end's numba kernels, e.g. before a ROS node's first
        lockstep ack; default: nothing to load."""

    # --- what callers read from a running back-end
    @property
    def map_extent(self) -> tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax) m, see :meth:`extent_of`."""
        return self.extent_of(self.params)

    @property
    def map_update_interval(self) -> float:
        """s between two map publications (as slam_gmapping's ``map_update_interval``)."""
        return float(self.params.map_update_interval)

    @property
    def beam_angles(self) -> np.ndarray:
        """The beam angles (rad) of the laser the back-end was built for: a scan must have as
        many readings."""
        raise NotImplementedError

    def update(self, odom_pose, scan_ranges, t: float) -> np.ndarray | None:
        """Feed one scan with the odometry pose at its time; the new map-frame pose if the scan
        was processed, else None."""
        raise NotImplementedError

    def map(self) -> OccupancyGrid:
        """The current map."""
        raise NotImplementedError

    def pose(self) -> np.ndarray:
        """The current best robot pose in the map frame."""
        raise NotImplementedError

    def map_to_odom(self) -> np.ndarray:
        """The odom frame's pose in the map frame."""
        raise NotImplementedError

    def trajectory(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(processed-scan numbers (K,), times s (K,), map-frame robot poses (K, 3)): the
        back-end's final estimate at each processed scan, oldest first."""
        raise NotImplementedError

    def entropy(self) -> float:
        """Pose uncertainty published on ``~entropy`` (only when > 0; default none)."""
        return 0.0

    def stats(self) -> dict:
        """Run statistics for ``slam run``'s stats.json (e.g. ``resamples``; the runner adds
        ``scans_processed`` when missing)."""
        return {}


# name -> factory, or "module:attribute" resolved on first use (keeps imports light)
_REGISTRY: dict[str, str | Callable[..., SlamBackend]] = {
    "gmapping": "slam_predict.slam.gmapping.filter:GMapping",
    "karto": "slam_predict.slam.karto.backend:Karto",
}
# other names users give a back-end (the ROS package that runs it)
ALIASES = {"slam_toolbox": "karto"}
# Modules (or .py files) that register more back-ends, comma-separated; imported once, on the
# first look-up, as are the ``slam_predict.slam_backends`` entry points of installed packages.
EXTRA_BACKENDS_ENV = "SLAM_PREDICT_EXTRA_BACKENDS"
ENTRY_POINT_GROUP = "slam_predict.slam_backends"
_plugins_loaded = False


def register(name: str, factory: str | Callable[..., SlamBackend]) -> None:
    """Register a back-end factory under ``name``; duplicate names are refused."""
    if name in _REGISTRY:
        raise ValueError(f"SLAM back-end '{name}' is already registered")
    _REGISTRY[name] = factory


def unregister(name: str) -> None:
    """Remove a registered back-end (tests that register their own)."""
    _REGISTRY.pop(name, None)


def load_plugins() -> None:
    """Import the back-end modules named by ``$SLAM_PREDICT_EXTRA_BACKENDS`` and the
    ``slam_predict.slam_backends`` entry points (once); each registers its back-ends."""
    global _plugins_loaded
    if _plugins_loaded:
        return
    _plugins_loaded = True
    from slam_predict.slam.plugins import import_plugins
    import_plugins(os.environ.get(EXTRA_BACKENDS_ENV, ""), ENTRY_POINT_GROUP)


def available() -> tuple[str, ...]:
    """Registered back-end names."""
    load_plugins()
    return tuple(sorted(_REGISTRY))


def backend_class(name: str):
    """The factory registered as ``name`` (InputError with a did-you-mean when unknown)."""
    load_plugins()
    if name not in _REGISTRY:
        raise InputError(f"unknown SLAM type '{name}'" + did_you_mean(name, _REGISTRY))
    factory = _REGISTRY[name]
    if isinstance(factory, str):
        module, attr = factory.split(":")
        factory = getattr(importlib.import_module(module), attr)
        _REGISTRY[name] = factory
    return factory


def canonical_name(name: str, option: str = "--slam") -> str:
    """The registered back-end a user's name means (:data:`ALIASES` resolved); an unknown one
    is an InputError naming ``option`` and the known names."""
    name = ALIASES.get(name, name)
    known = available()
    if name not in known:
        names = sorted((*known, *ALIASES))
        raise InputError(f"{option} {name}: unknown SLAM back-end"
                         + did_you_mean(name, names) + f" (known: {', '.join(names)})")
    return name


def create(name: str, **kwargs) -> SlamBackend:
    """Instantiate the back-end registered as ``name`` with ``kwargs``."""
    return backend_class(name)(**kwargs)


def params_from_dict(name: str, data, source: str = "<config>"):
    """Parameters of back-end ``name`` from a mapping (``None``: its defaults)."""
    cls = backend_class(name)
    return cls.default_params() if data is None else cls.params_from_dict(data, source)


def load_params(name: str, path: os.PathLike | str):
    """Parameters of back-end ``name`` from a YAML file (a ``type:`` in it must agree)."""
    from slam_predict.config import load_yaml
    return params_from_dict(name, load_yaml(path) or {}, os.fspath(path))


def type_in(data, default: str = "gmapping") -> str:
    """The back-end a SLAM parameter mapping names with ``type:`` (``default`` when absent)."""
    return str(data.get("type", default)) if isinstance(data, dict) else default


@dataclass
class SlamChoice:
    """A configured back-end: its registered name and its parameter object."""

    type: str
    params: Any

    def params_hash(self) -> str:
        """Short hash of the parameters (as run.json's ``config_hashes``)."""
        from slam_predict.config import config_hash
        return config_hash(self.params)

    def record(self) -> dict[str, str]:
        """run.json's ``slam`` entry: the back-end's name and its parameters' hash."""
        return {"type": self.type, "params_hash": self.params_hash()}
