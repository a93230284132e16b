"""The pose-graph optimisation slam_toolbox's default Ceres solver sets up: one (x, y, yaw)
node per scan, the first held fixed; per edge the residual L·(R(yaw_a)ᵀ(p_b − p_a) − d_xy,
wrap(yaw_b − yaw_a − d_yaw)) with L the lower Cholesky factor of the edge's information matrix
(as its PoseGraph2dErrorTerm); Levenberg–Marquardt on the sparse normal equations (scipy)."""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

MAX_ITERATIONS = 50          # Ceres defaults
FUNCTION_TOLERANCE = 1e-6
GRADIENT_TOLERANCE = 1e-10
PARAMETER_TOLERANCE = 1e-8
INITIAL_RADIUS = 1e4


def wrap(angle):
    """Angles to [−π, π) (rad), as Ceres' NormalizeAngle."""
    return angle - 2.0 * np.pi * np.floor((angle + np.pi) / (2.0 * np.pi))


class PoseGraphSolver:
    """Nodes (kept between solves, as the Ceres solver's map) and constraints."""

    def __init__(self):
        self.nodes: list[np.ndarray] = []
        self.edges: list[tuple[int, int, np.ndarray, np.ndarray]] = []

    def add_node(self, pose) -> None:
        self.nodes.append(np.array(pose, float))

    def add_constraint(self, source: int, target: int, difference, covariance) -> None:
        """An edge: ``difference`` (x, y, yaw) of target in source's frame; ``covariance`` 3×3."""
        information = np.linalg.inv(np.asarray(covariance, float))
        sqrt_information = np.linalg.cholesky(information)
        self.edges.append((source, target, np.asarray(difference, float), sqrt_information))

    def solve(self) -> np.ndarray:
        """Optimise; the nodes (N, 3) after it (also kept for the next solve)."""
        if len(self.nodes) < 2 or not self.edges:
            return np.array(self.nodes)
        x = np.array(self.nodes)
        x = levenberg_marquardt(x, self._arrays())
        self.nodes = [row.copy() for row in x]
        return x

    def _arrays(self):
        src = np.array([e[0] for e in self.edges])
        dst = np.array([e[1] for e in self.edges])
        diff = np.array([e[2] for e in self.edges])
        sqrt_info = np.array([e[3] for e in self.edges])
        return src, dst, diff, sqrt_info


def residuals_and_jacobian(x, edges):
    """Weighted residuals (3m,) and their sparse Jacobian (3m × 3n) at poses ``x`` (n, 3)."""
    src, dst, diff, sqrt_info = edges
    xa, xb = x[src], x[dst]
    c, s = np.cos(xa[:, 2]), np.sin(xa[:, 2])
    dx, dy = xb[:, 0] - xa[:, 0], xb[:, 1] - xa[:, 1]
    raw = np.column_stack((c * dx + s * dy - diff[:, 0], -s * dx + c * dy - diff[:, 1],
                           wrap(xb[:, 2] - xa[:, 2] - diff[:, 2])))
    m = len(src)
    block_a = np.zeros((m, 3, 3))
    block_a[:, 0, 0], block_a[:, 0, 1], block_a[:, 0, 2] = -c, -s, -s * dx + c * dy
    block_a[:, 1, 0], block_a[:, 1, 1], block_a[:, 1, 2] = s, -c, -c * dx - s * dy
    block_a[:, 2, 2] = -1.0
    block_b = np.zeros((m, 3, 3))
    block_b[:, 0, 0], block_b[:, 0, 1] = c, s
    block_b[:, 1, 0], block_b[:, 1, 1] = -s, c
    block_b[:, 2, 2] = 1.0
    residual = np.einsum("kij,kj->ki", sqrt_info, raw).reshape(-1)
    ja = np.einsum("kij,kjl->kil", sqrt_info, block_a)
    jb = np.einsum("kij,kjl->kil", sqrt_info, block_b)
    rows = np.repeat(np.arange(3 * m).reshape(m, 3, 1), 3, axis=2)
    cols_a = 3 * src[:, None, None] + np.arange(3)[None, None, :] + 0 * rows
    cols_b = 3 * dst[:, None, None] + np.arange(3)[None, None, :] + 0 * rows
    jac = sp.csr_matrix((np.concatenate((ja.ravel(), jb.ravel())),
                         (np.concatenate((rows.ravel(), rows.ravel())),
                          np.concatenate((cols_a.ravel(), cols_b.ravel())))),
                        shape=(3 * m, 3 * len(x)))
    return residual, jac


def levenberg_marquardt(x0, edges) -> np.ndarray:
    """Minimise ½‖r‖² over every node but the first (n, 3) with Ceres-style LM steps."""
    x = x0.copy()
    free = np.arange(3, 3 * len(x))
    radius, decrease = INITIAL_RADIUS, 2.0
    r, jac = residuals_and_jacobian(x, edges)
    cost = 0.5 * r @ r
    for _ in range(MAX_ITERATIONS):
        j = jac[:, free]
        gradient = j.T @ r
        if np.max(np.abs(gradient), initial=0.0) <= GRADIENT_TOLERANCE:
            break
        normal = (j.T @ j).tocsc()
        diagonal = np.clip(normal.diagonal(), 1e-6, 1e32)
        step = spsolve(normal + sp.diags(diagonal / radius, format="csc"), -gradient)
        trial = x.copy()
        trial.reshape(-1)[free] += step
        trial[:, 2] = wrap(trial[:, 2])
        r_new, jac_new = residuals_and_jacobian(trial, edges)
        cost_new = 0.5 * r_new @ r_new
        model = -(step @ gradient) - 0.5 * step @ (normal @ step)
        rho = (cost - cost_new) / model if model > 0 else -1.0
        if rho > 1e-3:
            converged = abs(cost - cost_new) <= FUNCTION_TOLERANCE * cost
            scale = np.linalg.norm(x) + PARAMETER_TOLERANCE
            small = np.linalg.norm(step) <= PARAMETER_TOLERANCE * scale
            x, r, jac, cost = trial, r_new, jac_new, cost_new
            radius = radius / max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3)
            decrease = 2.0
            if converged or small:
                break
        else:
            radius /= decrease
            decrease *= 2.0
            if radius < 1e-32:
                break
    return x

