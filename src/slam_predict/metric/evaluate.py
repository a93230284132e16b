"""Evaluate recorded trajectories: time association, thesis adjustments, pair selection.

Two modes: an estimated trajectory against a reference trajectory (pairs chosen on the
associated poses), or against a Freiburg relations file (metricEvaluator's way: each relation
timestamp takes the nearest estimated pose within ``tol``; unmatched relations are skipped).
"""
from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from slam_predict.errors import InputError
from slam_predict.formats.relations import Relations
from slam_predict.metric.association import associate, dedupe_consecutive, nearest_within
from slam_predict.metric.kummerle import (
    MetricResult,
    RelationMetric,
    evaluate_all_pairs,
    evaluate_pairs,
    evaluate_random,
    evaluate_sampled,
)
from slam_predict.metric.relations import (
    PairSelection,
    consecutive_pairs,
    random_forward_pairs,
    relation_deltas,
)

log = logging.getLogger(__name__)

DEFAULT_TOL = 0.01            # s, trajectory ↔ trajectory (evo's --t_max_diff default)
RELATIONS_TOL = 0.1           # s, relation timestamp ↔ pose (metricEvaluator)


@dataclass
class StampedPoses:
    """Timestamps ``t`` (N,) s and planar ``poses`` (N, 3)."""

    t: np.ndarray
    poses: np.ndarray

    def __post_init__(self):
        self.t = np.asarray(self.t, dtype=float).reshape(-1)
        self.poses = np.asarray(self.poses, dtype=float).reshape(-1, 3)
        if len(self.t) != len(self.poses):
            raise ValueError("timestamps and poses differ in length")


def aligned(est: StampedPoses, ref: StampedPoses, tol: float = DEFAULT_TOL, dedupe: bool = True):
    """Index-aligned (t, est poses, ref poses) after pause removal on the reference and
    one-to-one association within ``tol`` s."""
    ref_t, ref_p = dedupe_consecutive(ref.t, ref.poses) if dedupe else (ref.t, ref.poses)
    order_e = np.argsort(est.t, kind="stable")
    order_r = np.argsort(ref_t, kind="stable")
    ie, ir = associate(est.t[order_e], ref_t[order_r], tol)
    return ref_t[order_r][ir], est.poses[order_e][ie], ref_p[order_r][ir]


def evaluate_trajectories(est: StampedPoses, ref: StampedPoses, *,
                          pairs: PairSelection | int = PairSelection.AUTO,
                          rng: np.random.Generator | None = None, delta: int = 1,
                          tol: float = DEFAULT_TOL, dedupe: bool = True, ddof: int = 1,
                          source: str = "") -> MetricResult:
    """Relation error of ``est`` against ``ref``.

    ``pairs``: an int n (n random forward pairs), RANDOM (needs n — use an int), ALL, CONSECUTIVE
    (``delta`` frames) or AUTO (thesis pilot + sample size). Random selections need ``rng``.
    """
    t, est_p, ref_p = aligned(est, ref, tol, dedupe)
    info = {"associated": int(len(t)), "estimate_poses": int(len(est.t)),
            "reference_poses": int(len(ref.t)), "t_max_diff": tol, "dedupe": dedupe}
    if len(t) < 2:
        raise InputError(f"only {len(t)} poses matched within {tol} s: cannot form relations",
                         source or None)
    if isinstance(pairs, int) or pairs in (PairSelection.RANDOM, PairSelection.AUTO):
        if rng is None:
            raise ValueError("random pair selection needs a numpy Generator")
    if isinstance(pairs, (int, np.integer)) and not isinstance(pairs, bool):
        result = evaluate_random(est_p, ref_p, int(pairs), rng, ddof)
    elif pairs is PairSelection.AUTO:
        result = evaluate_sampled(est_p, ref_p, rng, ddof=ddof)
    elif pairs is PairSelection.ALL:
        result = evaluate_all_pairs(est_p, ref_p, ddof)
    elif pairs is PairSelection.CONSECUTIVE:
        result = evaluate_pairs(est_p, ref_p, consecutive_pairs(len(t), delta), ddof,
                                selection=f"consecutive pairs, delta {delta} frames")
    else:
        raise ValueError(f"unsupported pair selection {pairs!r}")
    result.info.update(info)
    return result


def sample_relations(ref: StampedPoses, n_pairs: int, rng: np.random.Generator,
                     dedupe: bool = True) -> Relations:
    """Random forward relations of the reference, as a metricEvaluator relations set."""
    t, poses = dedupe_consecutive(ref.t, ref.poses) if dedupe else (ref.t, ref.poses)
    pairs = random_forward_pairs(len(t), n_pairs, rng)
    return Relations(t[pairs[:, 0]], t[pairs[:, 1]], relation_deltas(poses, pairs))


def evaluate_relations(est: StampedPoses, relations: Relations, tol: float = RELATIONS_TOL,
                       ddof: int = 1, source: str = "") -> MetricResult:
    """Relation error of ``est`` against reference relations looked up by timestamp."""
    order = np.argsort(est.t, kind="stable")
    t, poses = est.t[order], est.poses[order]
    i = nearest_within(relations.t1, t, tol)
    j = nearest_within(relations.t2, t, tol)
    ok = (i >= 0) & (j >= 0)
    skipped = int((~ok).sum())
    if skipped:
        log.warning("%d of %d relations have no estimated pose within %.3f s; skipped",
                    skipped, len(relations), tol)
    if not ok.any():
        raise InputError(f"no relation timestamp matches an estimated pose within {tol} s",
                         source or None)
    pairs = np.column_stack([i[ok], j[ok]])
    metric = RelationMetric(ddof, keep_errors=False)
    metric.process_deltas(relation_deltas(poses, pairs), relations.deltas[ok])
    return metric.get_result(selection=f"{int(ok.sum())} relations from file", skipped=skipped,
                             t_max_diff=tol)
