"""Feature vectors of a folder of worlds (e.g. the one ``worlds import-thesis`` writes).

Each building ``NAME`` is the plan file ``DIR/NAME.world`` (else ``DIR/NAME.<any plan suffix>``,
else ``DIR/NAME/NAME.world``); features are computed with
:func:`slam_predict.features.vector.compute_features` in worker processes. The feature
version is ``features.vector.feature_version``: the definition version plus the hash of the
full feature configuration, so models refuse feature vectors computed differently (the
configuration helpers live in :mod:`slam_predict.features.plan`).
"""
from __future__ import annotations

import logging
import os
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import Any

from slam_predict.errors import InputError
from slam_predict.features.plan import compute, full_feature_config, version_of
from slam_predict.world.load import PLAN_SUFFIXES

LOG = logging.getLogger(__name__)


def find_plan(folder: Path, name: str) -> Path | None:
    """The plan file of building ``name`` in ``folder``, or None."""
    for candidate in (folder / f"{name}.world", folder / name / f"{name}.world"):
        if candidate.is_file():
            return candidate
    for suffix in PLAN_SUFFIXES:
        if (folder / f"{name}{suffix}").is_file():
            return folder / f"{name}{suffix}"
    return None


def _one(path: str, config_dict: Mapping[str, Any],
         also: Callable[[Any], dict[str, float]] | None = None) -> dict[str, float]:
    from slam_predict.world.load import load_plan

    world = load_plan(path)
    values = compute(world, config_dict)
    if also is not None:
        values.update(also(world))
    return values


def features_from_worlds(folder: os.PathLike | str, names: Iterable[str],
                         feature_config: Mapping[str, Any] | None = None,
                         n_jobs: int = 1, also: Callable[[Any], dict[str, float]] | None = None
                         ) -> tuple[dict[str, dict[str, float]], str]:
    """({building: {feature: value}}, feature version) for the buildings that have a plan;
    ``also`` (a module-level function of the loaded World, e.g. the sight-line curve) adds
    its columns to each building's features, computed on the same load."""
    folder = Path(folder)
    if not folder.is_dir():
        raise InputError("worlds folder not found", folder)
    plans = {}
    for name in names:
        path = find_plan(folder, name)
        if path is None:
            LOG.info("no plan for %s in %s", name, folder)
        else:
            plans[name] = str(path)
    if not plans:
        raise InputError("no plan of any listed building in this folder", folder)
    LOG.info("computing features of %d buildings", len(plans))
    from joblib import Parallel, delayed

    config = full_feature_config(feature_config)
    values = Parallel(n_jobs=n_jobs)(delayed(_one)(p, config, also) for p in plans.values())
    return dict(zip(plans, values, strict=False)), version_of(config)
