"""The pose-graph solver: its Ceres-style trust-region LM against a plain dense re-statement of
Ceres 2.1's rules (numpy, one loop, no sparse algebra), its minimum against
scipy.optimize.least_squares, the Jacobian against finite differences and the edge weights
against the information matrix."""
import math

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.optimize import least_squares

from slam_predict.slam.karto.ceres_lm import CeresOptions, minimize
from slam_predict.slam.karto.solver import (
    PoseGraphSolver,
    karto_inverse,
    optimise,
    residuals_and_jacobian,
    sqrt_information,
    wrap,
)


def small_graph(rng, n=8, noise=0.05):
    truth = np.cumsum(rng.normal([0.5, 0.1, 0.2], [0.1, 0.1, 0.1], (n, 3)), axis=0)
    truth[0] = 0.0
    solver = PoseGraphSolver()
    for pose in truth + rng.normal(0, noise, truth.shape) * (np.arange(n) > 0)[:, None]:
        solver.add_node(pose)
    pairs = [(k, k + 1) for k in range(n - 1)] + [(0, n - 3), (2, n - 1), (1, n - 2)]
    for a, b in pairs:
        c, s = np.cos(truth[a, 2]), np.sin(truth[a, 2])
        d = truth[b] - truth[a]
        diff = np.array([c * d[0] + s * d[1], -s * d[0] + c * d[1], wrap(d[2])])
        cov = np.diag([0.01, 0.02, 0.005]) + 0.002
        cov[0, 1] = cov[1, 0] = 0.004
        solver.add_constraint(a, b, diff + rng.normal(0, 0.02, 3), cov)
    return solver


def dense_reference(x0, edges, o: CeresOptions):
    """Ceres 2.1's trust-region loop written out plainly: dense Jacobian, np.linalg.solve."""
    def res(free):
        return residuals_and_jacobian(np.vstack((x0[:1], free.reshape(-1, 3))), edges, False)[0]

    def jac(free):
        full = np.vstack((x0[:1], free.reshape(-1, 3)))
        return residuals_and_jacobian(full, edges)[1].toarray()[:, 3:]

    def plus(free, delta):
        out = (free + delta).reshape(-1, 3)
        out[:, 2] = wrap(out[:, 2])
        return out.reshape(-1)

    x = x0[1:].reshape(-1).copy()
    r, j = res(x), jac(x)
    scale = 1.0 / (1.0 + np.sqrt((j * j).sum(axis=0)))
    cost = 0.5 * r @ r
    best, best_cost = x.copy(), cost
    radius, factor, diagonal, reuse = o.initial_trust_region_radius, 2.0, None, False
    current = reference = minimum = candidate_ref = cost
    acc_ref = acc_cand = 0.0
    nonmono, x_norm, invalid = 0, -1.0, 0
    gradient_ok = np.max(np.abs(x - plus(x, -(j.T @ r)))) <= o.gradient_tolerance
    iteration, success = 0, True
    while (iteration < o.max_num_iterations and not (success and gradient_ok)
           and radius > o.min_trust_region_radius):
        iteration += 1
        success = False
        js = j * scale
        if not reuse:
            diagonal = np.clip((js * js).sum(axis=0), o.min_lm_diagonal, o.max_lm_diagonal)
        reuse = True
        step = np.linalg.solve(js.T @ js + np.diag(diagonal / radius), -(js.T @ r))
        model = -(js @ step) @ (r + (js @ step) / 2.0)
        if model <= 0:
            invalid += 1
            assert invalid < o.max_num_consecutive_invalid_steps
            radius, factor = radius / factor, factor * 2.0
            continue
        invalid = 0
        trial = plus(x, step * scale)
        r_trial = res(trial)
        c_trial = 0.5 * r_trial @ r_trial
        if np.linalg.norm(x - trial) <= o.parameter_tolerance * (x_norm + o.parameter_tolerance):
            break
        if abs(cost - c_trial) <= o.function_tolerance * cost:
            break
        quality = max((current - c_trial) / model, (reference - c_trial) / (acc_ref + model))
        if quality > o.min_relative_decrease:
            x, r, j, cost, x_norm = trial, r_trial, jac(trial), c_trial, np.linalg.norm(trial)
            radius = min(o.max_trust_region_radius,
                         radius / max(1 / 3, 1 - (2 * quality - 1) ** 3))
            factor, reuse, success = 2.0, False, True
            current, acc_cand, acc_ref = c_trial, acc_cand + model, acc_ref + model
            if c_trial < minimum:
                minimum, candidate_ref, nonmono, acc_cand = c_trial, c_trial, 0, 0.0
            else:
                nonmono += 1
                if c_trial > candidate_ref:
                    candidate_ref, acc_cand = c_trial, 0.0
            if nonmono == o.max_consecutive_nonmonotonic_steps:
                reference, acc_ref = candidate_ref, acc_cand
            if cost < best_cost:
                best, best_cost = x.copy(), cost
            gradient_ok = np.max(np.abs(x - plus(x, -(j.T @ r)))) <= o.gradient_tolerance
        else:
            radius, factor, reuse = radius / factor, factor * 2.0, True
    return np.vstack((x0[:1], best.reshape(-1, 3))), iteration


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("tolerance", [1e-3, 1e-9])
def test_steps_equal_a_dense_statement_of_ceres_rules(seed, tolerance):
    rng = np.random.default_rng(seed)
    solver = small_graph(rng, n=10, noise=0.3)
    start, edges = np.array(solver.nodes), solver._arrays()
    options = CeresOptions(function_tolerance=tolerance, parameter_tolerance=tolerance)
    expected, iterations = dense_reference(start, edges, options)
    ours, summary = optimise(start, edges, options)
    assert summary.iterations == iterations
    assert np.allclose(ours, expected, atol=1e-9)


def test_tight_tolerances_reach_the_least_squares_minimum():
    rng = np.random.default_rng(3)
    solver = small_graph(rng)
    start, edges = np.array(solver.nodes), solver._arrays()

    def fun(free):
        return residuals_and_jacobian(np.vstack((start[:1], free.reshape(-1, 3))), edges)[0]

    reference = least_squares(fun, start[1:].ravel(), xtol=1e-14, ftol=1e-14, gtol=1e-14)
    tight = CeresOptions(function_tolerance=1e-14, parameter_tolerance=1e-14,
                         gradient_tolerance=1e-14)
    ours, summary = optimise(start, edges, tight)
    assert summary.usable()
    assert np.allclose(ours[0], start[0])
    assert np.allclose(ours[1:, :2], reference.x.reshape(-1, 3)[:, :2], atol=1e-7)
    assert np.allclose(wrap(ours[1:, 2] - reference.x.reshape(-1, 3)[:, 2]), 0.0, atol=1e-7)


def test_slam_toolbox_tolerances_stop_early_at_a_lower_cost_point():
    rng = np.random.default_rng(5)
    solver = small_graph(rng, noise=0.3)
    start = np.array(solver.nodes)
    cost0 = 0.5 * np.sum(residuals_and_jacobian(start, solver._arrays(), False)[0] ** 2)
    poses = solver.solve()
    summary = solver.summaries[-1]
    assert summary.termination == "CONVERGENCE" and summary.final_cost < cost0
    assert np.allclose(poses[0], start[0])
    assert np.allclose(np.array(solver.nodes), poses)


def test_a_linear_least_squares_problem_is_solved_through_the_scaled_space():
    a = np.array([[3.0, 1.0], [0.0, 200.0], [1.0, 1.0]])
    b = np.array([1.0, -2.0, 0.5])
    tight = CeresOptions(function_tolerance=1e-15, parameter_tolerance=1e-15,
                         gradient_tolerance=1e-12)
    x, summary = minimize(np.zeros(2), lambda x: a @ x - b, lambda x: sp.csr_matrix(a),
                          lambda x, d: x + d, tight)
    assert np.allclose(x, np.linalg.lstsq(a, b, rcond=None)[0], atol=1e-6)
    assert summary.usable()


def test_jacobian_matches_finite_differences():
    rng = np.random.default_rng(4)
    solver = small_graph(rng)
    x = np.array(solver.nodes)
    edges = solver._arrays()
    r0, jac = residuals_and_jacobian(x, edges)
    numeric = np.zeros(jac.shape)
    for k in range(x.size):
        step = np.zeros(x.size)
        step[k] = 1e-7
        numeric[:, k] = (residuals_and_jacobian(x + step.reshape(x.shape), edges)[0] - r0) / 1e-7
    assert np.allclose(jac.toarray(), numeric, atol=1e-5)


def test_edge_weight_is_the_upper_cholesky_factor_of_the_information():
    rng = np.random.default_rng(6)
    for _ in range(20):
        m = rng.normal(size=(3, 3))
        cov = m @ m.T + 0.1 * np.eye(3)
        assert np.allclose(karto_inverse(cov), np.linalg.inv(cov), rtol=1e-10)
        u = sqrt_information(cov)
        assert np.allclose(np.tril(u, -1), 0.0)
        assert np.allclose(u.T @ u, np.linalg.inv(cov), rtol=1e-9)
        r = rng.normal(size=3)
        assert math.isclose(np.sum((u @ r) ** 2), r @ np.linalg.solve(cov, r), rel_tol=1e-9)


def test_karto_inverse_of_a_near_singular_matrix_keeps_the_cofactors():
    cov = np.diag([1e-5, 1e-5, 1e-5])
    assert np.allclose(karto_inverse(cov), np.diag([1e-10, 1e-10, 1e-10]))
