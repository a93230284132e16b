"""slam_toolbox's Karto parameters: its names, the online_async yaml's values and the Mapper's
own defaults for the keys the yaml leaves out (units m, rad, s; docs/karto.md).

Ours: ``xmin``/``ymin``/``xmax``/``ymax`` (m, the canvas the published map is cut to) and
``scan_gate`` (``sync``: slam_toolbox's ``shouldProcessScan`` in front of the Mapper, as the sync
node; ``none``: every scan goes to the Mapper, as the async node when it is never busy;
``async``: the async node in real time, scans that arrive while the mapper is busy wait in a
queue or are dropped, costs ``async_cost``: :mod:`slam_predict.slam.karto.realtime`).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

from slam_predict.config import (
    AT_LEAST_ONE,
    NON_NEGATIVE,
    POSITIVE,
    PROBABILITY,
    Range,
    from_dict,
)
from slam_predict.errors import InputError
from slam_predict.slam import SlamNodeParams
from slam_predict.slam.karto.realtime import AsyncCost

NAME = "karto"
GATES = ("sync", "none", "async")


@dataclass
class KartoParams(SlamNodeParams):
    """slam_toolbox parameters (mapper_params_online_async.yaml) and the frames of the node."""

    transform_publish_period: float = 0.02
    map_update_interval: float = 5.0
    resolution: float = 0.05
    max_laser_range: float = 20.0
    minimum_time_interval: float = 0.5
    use_scan_matching: bool = True
    use_scan_barycenter: bool = True
    minimum_travel_distance: float = 0.5
    minimum_travel_heading: float = 0.5
    scan_buffer_size: int = 10
    scan_buffer_maximum_scan_distance: float = 10.0
    link_match_minimum_response_fine: float = 0.1
    link_scan_maximum_distance: float = 1.5
    loop_search_maximum_distance: float = 3.0
    do_loop_closing: bool = True
    loop_match_minimum_chain_size: int = 10
    loop_match_maximum_variance_coarse: float = 3.0
    loop_match_minimum_response_coarse: float = 0.35
    loop_match_minimum_response_fine: float = 0.45
    correlation_search_space_dimension: float = 0.5
    correlation_search_space_resolution: float = 0.01
    correlation_search_space_smear_deviation: float = 0.1
    loop_search_space_dimension: float = 8.0
    loop_search_space_resolution: float = 0.05
    loop_search_space_smear_deviation: float = 0.03
    distance_variance_penalty: float = 0.5
    angle_variance_penalty: float = 1.0
    fine_search_angle_offset: float = 0.00349
    coarse_search_angle_offset: float = 0.349
    coarse_angle_resolution: float = 0.0349
    minimum_angle_penalty: float = 0.9
    minimum_distance_penalty: float = 0.5
    use_response_expansion: bool = True
    # OccupancyGrid's own (not in the yaml): cells need more passes, hits over passes above this
    min_pass_through: int = 2
    occupancy_threshold: float = 0.1
    # ours
    scan_gate: str = "sync"
    xmin: float = -100.0
    ymin: float = -100.0
    xmax: float = 100.0
    ymax: float = 100.0
    async_cost: AsyncCost = field(default_factory=AsyncCost)
    HASH_OMIT_IF: ClassVar[dict] = {"async_cost": AsyncCost()}
    RANGES: ClassVar[dict[str, Range]] = {
        "throttle_scans": AT_LEAST_ONE, "transform_publish_period": NON_NEGATIVE,
        "tf_delay": NON_NEGATIVE, "map_update_interval": POSITIVE, "resolution": POSITIVE,
        "max_laser_range": POSITIVE, "minimum_time_interval": NON_NEGATIVE,
        "minimum_travel_distance": NON_NEGATIVE, "minimum_travel_heading": NON_NEGATIVE,
        "scan_buffer_size": AT_LEAST_ONE, "scan_buffer_maximum_scan_distance": POSITIVE,
        "link_match_minimum_response_fine": PROBABILITY, "link_scan_maximum_distance": POSITIVE,
        "loop_search_maximum_distance": POSITIVE, "loop_match_minimum_chain_size": AT_LEAST_ONE,
        "loop_match_maximum_variance_coarse": POSITIVE,
        "loop_match_minimum_response_coarse": PROBABILITY,
        "loop_match_minimum_response_fine": PROBABILITY,
        "correlation_search_space_dimension": POSITIVE,
        "correlation_search_space_resolution": POSITIVE,
        "correlation_search_space_smear_deviation": POSITIVE,
        "loop_search_space_dimension": POSITIVE, "loop_search_space_resolution": POSITIVE,
        "loop_search_space_smear_deviation": POSITIVE, "distance_variance_penalty": POSITIVE,
        "angle_variance_penalty": POSITIVE, "fine_search_angle_offset": POSITIVE,
        "coarse_search_angle_offset": POSITIVE, "coarse_angle_resolution": POSITIVE,
        "minimum_angle_penalty": PROBABILITY, "minimum_distance_penalty": PROBABILITY,
        "min_pass_through": NON_NEGATIVE, "occupancy_threshold": PROBABILITY}

    def __post_init__(self):
        if self.scan_gate not in GATES:
            raise ValueError(f"scan_gate must be one of {', '.join(GATES)}, got {self.scan_gate!r}")
        if self.xmax <= self.xmin or self.ymax <= self.ymin:
            raise ValueError("xmax/ymax must exceed xmin/ymin")


def params_from_dict(data, source: str = "<config>") -> KartoParams:
    """KartoParams from a mapping (strict; a ``type:`` entry must say ``karto``)."""
    data = dict(data or {})
    kind = data.pop("type", NAME)
    if kind != NAME:
        raise InputError(f"SLAM type '{kind}' is not {NAME}", source)
    return from_dict(KartoParams, data, source)
