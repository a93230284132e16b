"""Relation errors: hand-computed cases, evo's RPE as the reference, pair selectors."""
from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from evo.core import lie_algebra as lie
from evo.core import metrics
from evo.core.trajectory import PosePath3D
from metric_trajgen import perturbed, random_walk

from slam_predict.geometry import yaw_to_quaternion
from slam_predict.metric.relations import consecutive_pairs, random_forward_pairs, relation_errors


def test_hand_computed_translation_error():
    # Reference: 1 m straight ahead. Estimate: 1 m ahead after a 90° left turn at the start.
    ref = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    est = np.array([[0.0, 0.0, math.pi / 2], [0.0, 1.0, math.pi / 2]])
    err = relation_errors(est, ref, [[0, 1]])
    # δ (est) = (1, 0, 0) in the frame of pose 0, identical to δ*: no error.
    assert err.trans[0] == pytest.approx(0.0, abs=1e-15)
    assert err.rot[0] == pytest.approx(0.0, abs=1e-15)


def test_hand_computed_rotated_displacement():
    ref = np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]])
    est = np.array([[1.0, 1.0, 0.0], [3.0, 1.5, 0.3]])
    err = relation_errors(est, ref, [[0, 1]])
    # δ = (2, 0.5, 0.3); δ* = (2, 0, 0); e = δ* ⁻¹ δ = (0, 0.5, 0.3).
    assert err.trans[0] == pytest.approx(0.5, abs=1e-15)
    assert err.rot[0] == pytest.approx(0.3, abs=1e-15)


def test_error_expressed_in_reference_relation_frame():
    # δ* = (0, 0, π/2); δ = (1, 0, π/2): e = δ*⁻¹ δ = rotate (1, 0) by −π/2 → (0, −1), angle 0.
    ref = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, math.pi / 2]])
    est = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, math.pi / 2]])
    err = relation_errors(est, ref, [[0, 1]])
    assert err.trans[0] == pytest.approx(1.0) and err.rot[0] == pytest.approx(0.0, abs=1e-15)


def test_rotation_error_wraps():
    ref = np.array([[0.0, 0.0, 3.1], [0.0, 0.0, -3.1]])     # +0.0832 rad turn across ±π
    est = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    err = relation_errors(est, ref, [[0, 1]])
    assert err.rot[0] == pytest.approx(2 * math.pi - 6.2, abs=1e-12)


def test_invariant_to_global_rigid_motion(trajectories):
    est, ref = trajectories
    c, s = math.cos(0.7), math.sin(0.7)
    moved = np.column_stack([c * est[:, 0] - s * est[:, 1] + 5, s * est[:, 0] + c * est[:, 1] - 2,
                             est[:, 2] + 0.7])
    pairs = random_forward_pairs(len(ref), 200, np.random.default_rng(1))
    a, b = relation_errors(est, ref, pairs), relation_errors(moved, ref, pairs)
    np.testing.assert_allclose(a.trans, b.trans, atol=1e-9)
    np.testing.assert_allclose(a.rot, b.rot, atol=1e-9)


def _evo_path(poses):
    quat_xyzw = yaw_to_quaternion(poses[:, 2])
    wxyz = quat_xyzw[:, [3, 0, 1, 2]]
    xyz = np.column_stack([poses[:, 0], poses[:, 1], np.zeros(len(poses))])
    return PosePath3D(positions_xyz=xyz, orientations_quat_wxyz=wxyz)


@pytest.mark.parametrize("seed, delta", [(0, 1), (1, 1), (2, 7)])
def test_equals_evo_rpe_all_pairs(seed, delta):
    rng = np.random.default_rng(seed)
    ref = random_walk(rng, 400)
    est = perturbed(rng, ref)
    pairs = consecutive_pairs(len(ref), delta)
    ours = relation_errors(est, ref, pairs)
    data = (_evo_path(ref), _evo_path(est))
    for relation, mine in ((metrics.PoseRelation.translation_part, ours.trans),
                           (metrics.PoseRelation.rotation_angle_rad, ours.rot)):
        rpe = metrics.RPE(relation, delta=delta, delta_unit=metrics.Unit.frames, all_pairs=True)
        rpe.process_data(data)
        assert len(rpe.error) == len(mine)
        np.testing.assert_allclose(mine, rpe.error, atol=1e-9, rtol=0)


def test_equals_evo_rpe_base_on_random_forward_pairs():
    rng = np.random.default_rng(5)
    ref = random_walk(rng, 500)
    est = perturbed(rng, ref, sigma=(0.2, 0.2, 0.1))
    pairs = random_forward_pairs(len(ref), 2000, rng)
    ours = relation_errors(est, ref, pairs)
    p_ref, p_est = _evo_path(ref).poses_se3, _evo_path(est).poses_se3
    for k, (i, j) in enumerate(pairs):
        e = metrics.RPE.rpe_base(p_ref[i], p_ref[j], p_est[i], p_est[j])
        assert ours.trans[k] == pytest.approx(np.linalg.norm(e[:3, 3]), abs=1e-9)
        assert ours.rot[k] == pytest.approx(abs(lie.so3_log_angle(e[:3, :3])), abs=1e-9)


def test_random_forward_pairs_uniform_and_forward():
    rng = np.random.default_rng(0)
    pairs = random_forward_pairs(5, 100_000, rng)
    assert np.all(pairs[:, 0] < pairs[:, 1])
    counts = {}
    for i, j in map(tuple, pairs):
        counts[(i, j)] = counts.get((i, j), 0) + 1
    assert set(counts) == set(itertools.combinations(range(5), 2))
    freq = np.array(list(counts.values())) / len(pairs)
    np.testing.assert_allclose(freq, 0.1, atol=0.005)
    again = random_forward_pairs(5, 100_000, np.random.default_rng(0))
    np.testing.assert_array_equal(pairs, again)


def test_random_pairs_need_two_poses():
    with pytest.raises(ValueError):
        random_forward_pairs(1, 3, np.random.default_rng(0))
