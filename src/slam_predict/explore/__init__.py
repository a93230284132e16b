"""Frontier exploration and the in-process closed loop.

:mod:`~slam_predict.explore.frontiers` (frontier search), :mod:`~slam_predict.explore.explorer`
(goal choice), :mod:`~slam_predict.explore.mapsource` (the ``perfect`` map source),
:mod:`~slam_predict.explore.loop` (simulator + map source + navigator + explorer) and
:mod:`~slam_predict.explore.run` (one run end to end, as ``slam-predict explore``).
"""
