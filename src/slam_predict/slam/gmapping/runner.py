"""GMapping-specific checks of an offline run (:mod:`slam_predict.slam.runner`): how well its
map agrees with the map the reference poses give."""
from __future__ import annotations

import numpy as np

from slam_predict.slam.gmapping.params import GMappingParams
from slam_predict.slam.runner import RunResult
from slam_predict.slam.scans import SlamInput


def map_check(result: RunResult, data: SlamInput, tol: float = 2.0):
    """Map agreement of a GMapping run with the reference (see
    :func:`map_agreement_with_reference`)."""
    return map_agreement_with_reference(data, result.indices, result.poses, result.slam.params,
                                        tol)


def map_agreement_with_reference(data: SlamInput, indices: np.ndarray, poses: np.ndarray,
                                 params: GMappingParams, tol: float = 2.0):
    """(share of our occupied cells within ``tol`` cells of an occupied cell of the reference
    map, and the converse).

    ``poses`` are our map-frame robot poses at the input scans ``indices``. They are first fitted
    rigidly onto the reference poses; both maps are then built from the same scans with the
    published-map rules on a common geometry, the reference one from the reference poses.
    """
    from slam_predict.geometry import compose
    from slam_predict.slam.compare import apply_transform, map_agreement, rigid_fit
    from slam_predict.slam.gmapping.filter import centred_laser
    from slam_predict.slam.gmapping.gridmap import MapBuilder
    from slam_predict.slam.gmapping.params import with_ranges

    if data.reference is None:
        raise ValueError("the input has no reference poses")
    reference = data.reference[indices]
    laser_in_base, angles = centred_laser(data.laser)
    fitted = apply_transform(rigid_fit(poses, reference), poses)
    ours = compose(fitted, laser_in_base)
    ref = compose(reference, laser_in_base)
    readings = data.ranges[indices]
    builder = MapBuilder(with_ranges(params, data.laser.range_max), angles)
    geometry = builder.geometry(ref, readings, start=builder.geometry(ours, readings))
    a = builder.render(geometry, ours, readings)
    b = builder.render(geometry, ref, readings)
    return map_agreement(a.data, b.data, tol)
