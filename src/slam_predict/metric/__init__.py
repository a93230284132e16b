"""Kümmerle relation error, relation sampling, run statistics and run-count estimation.

Main entry points: :class:`RelationMetric` / :class:`MetricResult` (process → statistics →
serialisable result), :func:`evaluate_against_reference` (the GMapping yardstick),
:func:`evaluate_sampled` (thesis sampling), :func:`evaluate_trajectories` (recorded data),
:func:`building_statistics` and :func:`run_count` (per building).
"""
from slam_predict.metric.association import (
    associate,
    dedupe_consecutive,
    dedupe_mask,
    drop_truncated_last_line,
    nearest_within,
)
from slam_predict.metric.evaluate import (
    StampedPoses,
    evaluate_relations,
    evaluate_trajectories,
    sample_relations,
)
from slam_predict.metric.kummerle import (
    ErrorKind,
    MetricResult,
    RelationMetric,
    Variant,
    evaluate_against_reference,
    evaluate_all_pairs,
    evaluate_pairs,
    evaluate_random,
    evaluate_sampled,
)
from slam_predict.metric.relations import (
    PairSelection,
    RelationErrors,
    consecutive_pairs,
    random_forward_pairs,
    relation_errors,
)
from slam_predict.metric.runs import (
    BuildingStatistics,
    building_statistics,
    building_statistics_from_results,
)
from slam_predict.metric.sampling import (
    RunCountDecision,
    SampleSizeEstimate,
    relation_sample_size,
    required_sample_size,
    run_count,
    z_score,
)
from slam_predict.metric.stats import ErrorStatistics, compute_statistics

__all__ = [
    "associate", "dedupe_consecutive", "dedupe_mask", "drop_truncated_last_line", "nearest_within",
    "StampedPoses", "evaluate_relations", "evaluate_trajectories", "sample_relations", "ErrorKind",
    "MetricResult", "RelationMetric", "Variant", "evaluate_against_reference",
    "evaluate_all_pairs", "evaluate_pairs", "evaluate_random", "evaluate_sampled", "PairSelection",
    "RelationErrors", "consecutive_pairs", "random_forward_pairs", "relation_errors",
    "BuildingStatistics", "building_statistics", "building_statistics_from_results",
    "RunCountDecision", "SampleSizeEstimate", "relation_sample_size", "required_sample_size",
    "run_count", "z_score", "ErrorStatistics", "compute_statistics",
]
