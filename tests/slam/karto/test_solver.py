"""The sparse Levenberg–Marquardt pose-graph solver against scipy.optimize.least_squares."""
import numpy as np
from scipy.optimize import least_squares

from slam_predict.slam.karto.solver import PoseGraphSolver, residuals_and_jacobian, wrap


def small_graph(rng):
    truth = np.cumsum(rng.normal([0.5, 0.1, 0.2], [0.1, 0.1, 0.1], (8, 3)), axis=0)
    truth[0] = 0.0
    solver = PoseGraphSolver()
    for pose in truth + rng.normal(0, 0.05, truth.shape) * (np.arange(8) > 0)[:, None]:
        solver.add_node(pose)
    pairs = [(k, k + 1) for k in range(7)] + [(0, 5), (2, 7), (1, 6)]
    for a, b in pairs:
        c, s = np.cos(truth[a, 2]), np.sin(truth[a, 2])
        d = truth[b] - truth[a]
        diff = np.array([c * d[0] + s * d[1], -s * d[0] + c * d[1], wrap(d[2])])
        cov = np.diag([0.01, 0.02, 0.005]) + 0.002
        solver.add_constraint(a, b, diff + rng.normal(0, 0.02, 3), cov)
    return solver


def test_lm_reaches_least_squares_minimum():
    rng = np.random.default_rng(3)
    solver = small_graph(rng)
    start = np.array(solver.nodes)
    edges = solver._arrays()

    def fun(free):
        x = np.vstack((start[:1], free.reshape(-1, 3)))
        return residuals_and_jacobian(x, edges)[0]

    reference = least_squares(fun, start[1:].ravel(), xtol=1e-14, ftol=1e-14, gtol=1e-14)
    ours = solver.solve()
    assert np.allclose(ours[0], start[0])
    assert np.allclose(ours[1:, :2], reference.x.reshape(-1, 3)[:, :2], atol=1e-5)
    assert np.allclose(wrap(ours[1:, 2] - reference.x.reshape(-1, 3)[:, 2]), 0.0, atol=1e-5)


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
