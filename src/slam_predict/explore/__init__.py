"""Frontier exploration and the in-process closed loop.

:mod:`~slam_predict.explore.frontiers` (frontier search), :mod:`~slam_predict.explore.explorer`
(goal choice), :mod:`~slam_predict.explore.mapsource` (the ``perfect`` map source),
:mod:`~slam_predict.explore.loop` (simulator + map source + navigator + explorer) and
:mod:`~slam_predict.explore.run` (one run end to end, as ``slam-predict explore``).
"""
from __future__ import annotations

PERFECT = "perfect"


def map_sources() -> tuple[str, ...]:
    """The closed loop's map sources: ``perfect`` and every registered SLAM back-end."""
    from slam_predict import slam
    return (PERFECT,) + slam.available()
