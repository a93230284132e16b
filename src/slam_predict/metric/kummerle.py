"""Kümmerle et al. (2009) relation error, in the style of evo: process → statistics → result.

>>> metric = RelationMetric()
>>> metric.process_data(est_poses, ref_poses, pairs)          # doctest: +SKIP
>>> metric.get_statistics(ErrorKind.TRANSLATION, Variant.ABS)  # doctest: +SKIP

Four series are kept per relation set: |trans| (m), trans² (m²), |rot| (rad), rot² (rad²). The
thesis' ε (eq. 3.1) is the mean of the squared variants; the thesis' data release and
metricEvaluator's default report the mean of the absolute ones. Per-relation std uses ddof = 1
by default (Cartographer's n − 1).
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from enum import Enum

import numpy as np

from slam_predict.metric.relations import (
    RelationErrors,
    count_forward_pairs,
    delta_errors,
    random_forward_pairs,
    relation_errors,
)
from slam_predict.metric.sampling import (
    RELATION_CONFIDENCE,
    RELATION_MARGIN_ROT,
    RELATION_MARGIN_TRANS,
    RELATION_PILOT,
    relation_sample_size,
)
from slam_predict.metric.stats import ErrorStatistics, StreamingStatistics


class ErrorKind(Enum):
    TRANSLATION = "trans"
    ROTATION = "rot"


class Variant(Enum):
    ABS = "abs"
    SQR = "sqr"


SERIES = [(k, v) for k in ErrorKind for v in Variant]


def _key(kind: ErrorKind, variant: Variant) -> str:
    return f"{kind.value}_{variant.value}"


@dataclass
class MetricResult:
    """Statistics of one relation set, serialisable (``to_dict`` / ``from_dict`` / JSON).

    ``stats`` maps 'trans_abs' (m), 'trans_sqr' (m²), 'rot_abs' (rad), 'rot_sqr' (rad²) to
    :class:`ErrorStatistics`; ``info`` records how the pairs were chosen.
    """

    stats: dict[str, ErrorStatistics]
    info: dict = field(default_factory=dict)

    def get(self, kind: ErrorKind, variant: Variant = Variant.ABS) -> ErrorStatistics:
        return self.stats[_key(kind, variant)]

    @property
    def n_relations(self) -> int:
        return self.stats["trans_abs"].n

    def summary(self) -> dict:
        """Flat numbers: trans_mean/std (m), rot_mean/std (rad), the squared variants, n."""
        out = {}
        for name, key in (("trans", "trans_abs"), ("rot", "rot_abs"),
                          ("trans_sqr", "trans_sqr"), ("rot_sqr", "rot_sqr")):
            out[f"{name}_mean"] = self.stats[key].mean
            out[f"{name}_std"] = self.stats[key].std
        out["rot_mean_deg"] = math.degrees(out["rot_mean"])
        out["rot_std_deg"] = math.degrees(out["rot_std"])
        out["n"] = self.n_relations
        return out

    def to_dict(self) -> dict:
        return {"stats": {k: s.to_dict() for k, s in self.stats.items()}, "info": dict(self.info)}

    @classmethod
    def from_dict(cls, data: dict) -> MetricResult:
        return cls({k: ErrorStatistics.from_dict(v) for k, v in data["stats"].items()},
                   dict(data.get("info", {})))

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), indent=1, sort_keys=True)

    def table(self) -> str:
        """Four lines as Cartographer's relations metric prints them, plus N (thesis Table 3.1)."""
        s = self.stats
        deg = math.degrees(1.0)
        ra, rs = s["rot_abs"], s["rot_sqr"]
        lines = [
            f"Abs translational error {s['trans_abs'].mean:.5f} +/- {s['trans_abs'].std:.5f} m",
            f"Sqr translational error {s['trans_sqr'].mean:.5f} +/- {s['trans_sqr'].std:.5f} m^2",
            f"Abs rotational error {ra.mean:.5f} +/- {ra.std:.5f} rad"
            f" ({ra.mean * deg:.4f} +/- {ra.std * deg:.4f} deg)",
            f"Sqr rotational error {rs.mean:.7f} +/- {rs.std:.7f} rad^2"
            f" ({rs.mean * deg ** 2:.4f} +/- {rs.std * deg ** 2:.4f} deg^2)",
            f"N = {self.n_relations} relations ({self.info.get('selection', 'given pairs')}; "
            f"std ddof={s['trans_abs'].ddof})",
        ]
        return "\n".join(lines)


class RelationMetric:
    """Kümmerle's relation error over pose pairs; data may be processed in several chunks."""

    def __init__(self, ddof: int = 1, keep_errors: bool = True):
        self.ddof = ddof
        self.keep_errors = keep_errors
        self._acc = {_key(k, v): StreamingStatistics(ddof) for k, v in SERIES}
        self._errors: list[RelationErrors] = []

    def process_data(self, est_poses: np.ndarray, ref_poses: np.ndarray,
                     pairs: np.ndarray) -> RelationMetric:
        """Add the relations ``pairs`` (i < j rows) of two index-aligned trajectories (N, 3)."""
        pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
        if np.any(pairs[:, 0] >= pairs[:, 1]):
            raise ValueError("relations must go forward in time (i < j)")
        return self.process_errors(relation_errors(est_poses, ref_poses, pairs))

    def process_deltas(self, est_deltas: np.ndarray, ref_deltas: np.ndarray) -> RelationMetric:
        """Add relations given directly as displacements δ (estimate) and δ* (reference)."""
        return self.process_errors(delta_errors(est_deltas, ref_deltas))

    def process_errors(self, errors: RelationErrors) -> RelationMetric:
        self._acc["trans_abs"].update(errors.trans)
        self._acc["trans_sqr"].update(errors.trans ** 2)
        self._acc["rot_abs"].update(errors.rot)
        self._acc["rot_sqr"].update(errors.rot ** 2)
        if self.keep_errors:
            self._errors.append(errors)
        return self

    @property
    def errors(self) -> RelationErrors:
        """All per-relation errors processed so far (only with ``keep_errors``)."""
        if not self.keep_errors:
            raise RuntimeError("per-relation errors were not kept (keep_errors=False)")
        if not self._errors:
            return RelationErrors(np.zeros(0), np.zeros(0))
        return RelationErrors(np.concatenate([e.trans for e in self._errors]),
                              np.concatenate([e.rot for e in self._errors]))

    def get_statistics(self, kind: ErrorKind, variant: Variant = Variant.ABS) -> ErrorStatistics:
        return self._acc[_key(kind, variant)].result()

    def get_result(self, **info) -> MetricResult:
        return MetricResult({k: acc.result() for k, acc in self._acc.items()}, info)


def evaluate_pairs(est_poses, ref_poses, pairs, ddof: int = 1, **info) -> MetricResult:
    """Result over the given pairs of two index-aligned trajectories."""
    return RelationMetric(ddof, keep_errors=False).process_data(est_poses, ref_poses, pairs) \
        .get_result(**info)


def evaluate_random(est_poses, ref_poses, n_pairs: int, rng: np.random.Generator,
                    ddof: int = 1, **info) -> MetricResult:
    """Result over ``n_pairs`` random forward pairs drawn with ``rng``."""
    pairs = random_forward_pairs(len(ref_poses), n_pairs, rng)
    info.setdefault("selection", f"{n_pairs} random forward pairs")
    return evaluate_pairs(est_poses, ref_poses, pairs, ddof, **info)


def evaluate_against_reference(est_poses, ref_poses, n_pairs: int = 5000,
                               seed: int = 0) -> MetricResult:
    """The GMapping yardstick (shared/baselines/gmapping_real.md).

    ``n_pairs`` random forward pose pairs (numpy Generator seeded with ``seed``) over the
    index-aligned processed-scan poses; report e.g. ``summary()['trans_mean']`` (m) and
    ``summary()['rot_mean_deg']``.
    """
    return evaluate_random(est_poses, ref_poses, n_pairs, np.random.default_rng(seed), seed=seed)


def evaluate_all_pairs(est_poses, ref_poses, ddof: int = 1) -> MetricResult:
    """Exact result over every forward pair i < j (thesis eq. 3.1 in full), by a numba kernel."""
    from slam_predict.metric.kernels import SERIES as KERNEL_SERIES
    from slam_predict.metric.kernels import all_pairs_moments

    est = np.ascontiguousarray(est_poses, dtype=float).reshape(-1, 3)
    ref = np.ascontiguousarray(ref_poses, dtype=float).reshape(-1, 3)
    if len(est) != len(ref):
        raise ValueError(f"trajectories differ in length: {len(est)} vs {len(ref)}")
    moments = all_pairs_moments(est, ref)
    stats = {}
    for key, row in zip(KERNEL_SERIES, moments, strict=False):
        acc = StreamingStatistics(ddof)
        acc.merge(int(row[0]), *map(float, row[1:]))
        stats[key] = acc.result()
    return MetricResult(stats, {"selection": f"all {count_forward_pairs(len(ref))} forward pairs"})


def evaluate_sampled(est_poses, ref_poses, rng: np.random.Generator, *,
                     pilot: int = RELATION_PILOT, margin_trans: float = RELATION_MARGIN_TRANS,
                     margin_rot: float = RELATION_MARGIN_ROT,
                     confidence: float = RELATION_CONFIDENCE, ddof: int = 1) -> MetricResult:
    """The thesis' relations sampling (§4.2.3) on one run.

    A pilot of ``pilot`` random forward pairs gives the std of the per-relation absolute errors;
    n = ⌈z²s²/d²⌉ (larger of trans and rot); then n fresh random pairs give the result. When n
    reaches the number of distinct forward pairs, every pair is used instead (exact).
    """
    pilot_pairs = random_forward_pairs(len(ref_poses), pilot, rng)
    errors = relation_errors(est_poses, ref_poses, pilot_pairs)
    estimate = relation_sample_size(errors.trans, errors.rot, margin_trans, margin_rot, confidence)
    n = max(estimate.n, 2)
    info = {"pilot": pilot, "sample_size": estimate.to_dict()}
    if n >= count_forward_pairs(len(ref_poses)):
        result = evaluate_all_pairs(est_poses, ref_poses, ddof)
        result.info.update(info)
        return result
    return evaluate_random(est_poses, ref_poses, n, rng, ddof,
                           **{**info, "selection": f"{n} random forward pairs (pilot {pilot})"})
