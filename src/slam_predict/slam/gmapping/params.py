"""Every slam_gmapping parameter, with the node's code defaults (ros_interfaces.md §2.2).

Names are the ROS parameter names (private namespace of ``slam_gmapping``), so a user's YAML
file carries over unchanged, e.g. ``../shared/baselines/gmapping_real_<log>.yaml``. Units: m, rad,
s. ``maxRange``/``maxUrange`` may be left unset (None): the node derives them from the first scan
(``range_max − 0.01`` and ``maxRange``), see :func:`resolve_ranges`.

Four options are ours: ``reproduce_freecell_bug`` (default True, i.e. behave exactly like upstream
openslam_gmapping; False uses the intended "cell before the hit must be free" test),
``range_sensor_angles`` (default True: the scan matcher's beam angles are those of the RangeSensor
slam_gmapping builds, −N·inc/2 + i·inc, half a beam off the scan's own; False: the scan's angles),
``random_stream`` (default ``drand48``: the filter draws openslam_gmapping's own stream, POSIX
drand48 and pf_ran_gaussian, see :mod:`.drand48`; ``numpy``: the run's numpy Generator, the
only stream before this option existed) and ``drand48_seed`` (the seed slam_gmapping would pass
to ``sampleGaussian(1, seed)``, 0 … 2³² − 1; None: drawn from the run's numpy Generator, so a run
stays determined by its seed; not called ``seed`` so as not to clash with the node's ``~seed``).
"""
from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

from slam_predict.config import (
    AT_LEAST_ONE,
    NON_NEGATIVE,
    POSITIVE,
    PROBABILITY,
    Range,
    from_dict,
    load_yaml,
    to_dict,
)
from slam_predict.errors import InputError
from slam_predict.slam import SlamNodeParams

_Str = str  # the field ``str`` (a motion-noise parameter) shadows the builtin in the class body

# Constants of openslam_gmapping that slam_gmapping does not expose.
FULLNESS_THRESHOLD = 0.1
FREE_CELL_RATIO = math.sqrt(2.0)
ENLARGE_STEP = 10.0  # m
NULL_LIKELIHOOD = -0.5
PATCH_MAGNITUDE = 5  # patches of 32 x 32 cells
# Choices of ``random_stream``; largest ``drand48_seed`` (srand48 keeps 32 bits of its seed).
STREAMS = ("drand48", "numpy")
SEED_MAX = 2 ** 32 - 1


@dataclass
class GMappingParams(SlamNodeParams):
    """slam_gmapping parameters (defaults = slam_gmapping's code defaults); the ROS wrapper's
    frames, throttle_scans, transform_publish_period and tf_delay come first (the base class)."""

    map_update_interval: float = 5.0
    # --- laser
    maxRange: float | None = None          # None: first scan's range_max - 0.01
    maxUrange: float | None = None         # None: = maxRange
    # --- scan matcher
    minimumScore: float = 0.0
    sigma: float = 0.05
    kernelSize: int = 1
    lstep: float = 0.05
    astep: float = 0.05
    iterations: int = 5
    lsigma: float = 0.075
    ogain: float = 3.0
    lskip: int = 0
    # --- motion model
    srr: float = 0.1
    srt: float = 0.2
    str: float = 0.1
    stt: float = 0.2
    # --- update triggers and filter
    linearUpdate: float = 1.0
    angularUpdate: float = 0.5
    temporalUpdate: float = -1.0
    resampleThreshold: float = 0.5
    particles: int = 30
    # --- initial map
    xmin: float = -100.0
    ymin: float = -100.0
    xmax: float = 100.0
    ymax: float = 100.0
    delta: float = 0.05
    occ_thresh: float = 0.25
    # --- likelihood sampling: read by slam_gmapping but without effect on this code path
    llsamplerange: float = 0.01
    llsamplestep: float = 0.01
    lasamplerange: float = 0.005
    lasamplestep: float = 0.005
    # --- ours
    reproduce_freecell_bug: bool = True
    range_sensor_angles: bool = True          # filter beams as the node's RangeSensor sets them
    random_stream: _Str = "drand48"           # "drand48" (upstream's own stream) or "numpy"
    drand48_seed: int | None = None           # None: drawn from the run's numpy Generator
    # config_hash leaves these out at these values (the behaviour before the options existed).
    HASH_OMIT_IF: ClassVar[dict[str, Any]] = {"random_stream": "numpy", "drand48_seed": None}
    RANGES: ClassVar[dict[str, Range]] = {
        "throttle_scans": AT_LEAST_ONE, "transform_publish_period": NON_NEGATIVE,
        "tf_delay": NON_NEGATIVE, "map_update_interval": NON_NEGATIVE, "maxRange": POSITIVE,
        "maxUrange": POSITIVE, "minimumScore": NON_NEGATIVE, "sigma": POSITIVE,
        "kernelSize": NON_NEGATIVE, "lstep": NON_NEGATIVE, "astep": NON_NEGATIVE,
        "iterations": NON_NEGATIVE, "lsigma": POSITIVE, "ogain": POSITIVE, "lskip": NON_NEGATIVE,
        "srr": NON_NEGATIVE, "srt": NON_NEGATIVE, "str": NON_NEGATIVE, "stt": NON_NEGATIVE,
        "linearUpdate": NON_NEGATIVE, "angularUpdate": NON_NEGATIVE,
        "resampleThreshold": PROBABILITY, "particles": AT_LEAST_ONE, "delta": POSITIVE,
        "occ_thresh": PROBABILITY, "llsamplerange": NON_NEGATIVE, "llsamplestep": NON_NEGATIVE,
        "lasamplerange": NON_NEGATIVE, "lasamplestep": NON_NEGATIVE,
        "drand48_seed": Range(0.0, float(SEED_MAX))}

    def __post_init__(self):
        if self.particles < 1:
            raise ValueError("particles must be >= 1")
        if self.delta <= 0:
            raise ValueError("delta must be > 0")
        if self.throttle_scans < 1:
            raise ValueError("throttle_scans must be >= 1")
        if self.kernelSize < 0 or self.lskip < 0 or self.iterations < 0:
            raise ValueError("kernelSize, lskip and iterations must be >= 0")
        if self.xmax <= self.xmin or self.ymax <= self.ymin:
            raise ValueError("xmax/ymax must exceed xmin/ymin")
        for name in ("sigma", "lsigma", "ogain"):
            if getattr(self, name) <= 0:
                raise ValueError(f"{name} must be > 0")
        for name in ("srr", "srt", "str", "stt"):
            if getattr(self, name) < 0:
                raise ValueError(f"{name} must be >= 0")
        if self.random_stream not in STREAMS:
            raise ValueError(f"random_stream must be one of {', '.join(STREAMS)}, "
                             f"got {self.random_stream!r}")
        if self.drand48_seed is not None and not 0 <= self.drand48_seed <= SEED_MAX:
            raise ValueError(f"drand48_seed must be in [0, {SEED_MAX}]")


def params_from_dict(data: Mapping[str, Any] | None, source: _Str = "<config>") -> GMappingParams:
    """Strict construction from a mapping of slam_gmapping names (unknown keys rejected).

    A ``type: gmapping`` entry (the SLAM back-end selector) is accepted and ignored.
    """
    data = dict(data or {})
    kind = data.pop("type", "gmapping")
    if kind != "gmapping":
        raise InputError(f"SLAM type '{kind}' is not gmapping", source)
    return from_dict(GMappingParams, data, source)


def params_from_record(data: Mapping[str, Any], source: _Str = "<run record>") -> GMappingParams:
    """Parameters recorded by a run (run.json ``sensor_logs.gmapping``): as
    :func:`params_from_dict`, except that a record without ``random_stream`` predates that option
    and ran on the numpy stream, so it gets ``numpy`` (its replay reproduces it exactly)."""
    if isinstance(data, Mapping):
        data = {"random_stream": "numpy", **data}
    return params_from_dict(data, source)


def load_params(path: os.PathLike | _Str) -> GMappingParams:
    """Load a slam_gmapping parameter YAML (flat mapping; e.g. the baseline files as they are)."""
    return params_from_dict(load_yaml(path), os.fspath(path))


def params_to_dict(params: GMappingParams) -> dict:
    """Plain dict (for run metadata), the inverse of :func:`params_from_dict`."""
    return to_dict(params)


def resolve_ranges(params: GMappingParams, sensor_range_max: float) -> tuple[float, float]:
    """(maxRange, maxUrange) in m as slam_gmapping sets them at the first scan.

    maxRange defaults to the sensor's range_max − 0.01; maxUrange to maxRange.
    """
    max_range = params.maxRange
    if max_range is None:
        if not math.isfinite(sensor_range_max):
            raise ValueError("maxRange is not set and the sensor gives no range_max")
        max_range = float(sensor_range_max) - 0.01
    max_urange = max_range if params.maxUrange is None else params.maxUrange
    return float(max_range), float(max_urange)


def with_ranges(params: GMappingParams, sensor_range_max: float) -> GMappingParams:
    """A copy of ``params`` with maxRange/maxUrange filled in (see :func:`resolve_ranges`)."""
    max_range, max_urange = resolve_ranges(params, sensor_range_max)
    return dataclasses.replace(params, maxRange=max_range, maxUrange=max_urange)
