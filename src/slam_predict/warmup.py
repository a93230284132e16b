"""Compile every numba kernel once so later runs load them from the cache (``make setup``)."""
from __future__ import annotations

import importlib
import logging
import time

LOG = logging.getLogger(__name__)

# Modules exposing ``warmup()``: each compiles its kernels on a tiny input.
MODULES = (
    "slam_predict.sim.raycast",
    "slam_predict.sim.stage_ranger",
    "slam_predict.slam.gmapping.kernels",
    "slam_predict.slam.gmapping.raytrace",
    "slam_predict.slam.gmapping.drand48",
    "slam_predict.nav.kernels",
    "slam_predict.nav.footprint_helper",
    "slam_predict.nav.map_grid",
    "slam_predict.nav.changes",
    "slam_predict.explore.kernels",
    "slam_predict.features.kernels",
    "slam_predict.metric.kernels",
    "slam_predict.world.raster",
)


def warm_all() -> float:
    """Warm every module's kernels; returns the wall time in s."""
    start = time.perf_counter()
    for name in MODULES:
        importlib.import_module(name).warmup()
    return time.perf_counter() - start


if __name__ == "__main__":
    logging.basicConfig(level=logging.INFO)
    LOG.info("numba cache warm in %.1f s", warm_all())
