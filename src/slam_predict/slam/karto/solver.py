"""The pose-graph optimisation slam_toolbox's default Ceres solver sets up: one (x, y, yaw)
node per scan, the first held fixed; per edge the residual U·(R(yaw_a)ᵀ(p_b − p_a) − d_xy,
wrap(yaw_b − yaw_a − d_yaw)) with U the upper Cholesky factor of the edge's information matrix
(UᵀU = Karto's inverse of the covariance, as its PoseGraph2dErrorTerm); the angles move by
wrapped addition (its AngleLocalParameterization). Minimised with Ceres' trust-region
Levenberg–Marquardt as slam_toolbox configures it (``ceres_lm``)."""
from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp

from slam_predict.slam.karto.ceres_lm import CeresOptions, Summary, minimize

LOG = logging.getLogger(__name__)
INVERSE_TOLERANCE = 1e-14    # Karto's Matrix3::Inverse determinant tolerance


def wrap(angle):
    """Angles to [−π, π) (rad), as Ceres' NormalizeAngle."""
    return angle - 2.0 * np.pi * np.floor((angle + np.pi) / (2.0 * np.pi))


def karto_inverse(matrix) -> np.ndarray:
    """Karto's Matrix3::Inverse (cofactors over the determinant). Like Karto built without
    asserts, a determinant within 1e-14 of zero leaves the cofactor matrix undivided."""
    m = np.asarray(matrix, float)
    cof = np.empty((3, 3))
    cof[0, 0] = m[1, 1] * m[2, 2] - m[1, 2] * m[2, 1]
    cof[0, 1] = m[0, 2] * m[2, 1] - m[0, 1] * m[2, 2]
    cof[0, 2] = m[0, 1] * m[1, 2] - m[0, 2] * m[1, 1]
    cof[1, 0] = m[1, 2] * m[2, 0] - m[1, 0] * m[2, 2]
    cof[1, 1] = m[0, 0] * m[2, 2] - m[0, 2] * m[2, 0]
    cof[1, 2] = m[0, 2] * m[1, 0] - m[0, 0] * m[1, 2]
    cof[2, 0] = m[1, 0] * m[2, 1] - m[1, 1] * m[2, 0]
    cof[2, 1] = m[0, 1] * m[2, 0] - m[0, 0] * m[2, 1]
    cof[2, 2] = m[0, 0] * m[1, 1] - m[0, 1] * m[1, 0]
    det = m[0, 0] * cof[0, 0] + m[0, 1] * cof[1, 0] + m[0, 2] * cof[2, 0]
    if abs(det) <= INVERSE_TOLERANCE:
        return cof
    return cof * (1.0 / det)


def sqrt_information(covariance) -> np.ndarray:
    """U with UᵀU = the information matrix (Karto's inverse, mirrored from its upper triangle)."""
    precision = karto_inverse(covariance)
    upper = np.triu(precision)
    information = upper + np.triu(precision, 1).T
    return np.linalg.cholesky(information).T


class PoseGraphSolver:
    """Nodes (kept between solves, as the Ceres solver's map) and constraints."""

    def __init__(self, options: CeresOptions | None = None):
        self.options = options or CeresOptions()
        self.nodes: list[np.ndarray] = []
        self.edges: list[tuple[int, int, np.ndarray, np.ndarray]] = []
        self.summaries: list[Summary] = []

    def add_node(self, pose) -> None:
        self.nodes.append(np.array(pose, float))

    def add_constraint(self, source: int, target: int, difference, covariance) -> None:
        """An edge: ``difference`` (x, y, yaw) of target in source's frame; ``covariance`` 3×3."""
        self.edges.append((source, target, np.asarray(difference, float),
                           sqrt_information(covariance)))

    def solve(self) -> np.ndarray | None:
        """Optimise; the nodes (N, 3) after it (also kept for the next solve), or None when
        Ceres would report no usable solution (the nodes then stay as they were)."""
        if len(self.nodes) < 2 or not self.edges:
            return np.array(self.nodes)
        x, summary = optimise(np.array(self.nodes), self._arrays(), self.options)
        self.summaries.append(summary)
        if not summary.usable():
            LOG.warning("pose graph: no usable solution (%s)", summary.message)
            return None
        self.nodes = [row.copy() for row in x]
        return x

    def _arrays(self):
        src = np.array([e[0] for e in self.edges])
        dst = np.array([e[1] for e in self.edges])
        diff = np.array([e[2] for e in self.edges])
        sqrt_info = np.array([e[3] for e in self.edges])
        return src, dst, diff, sqrt_info


def optimise(nodes, edges, options: CeresOptions | None = None):
    """Ceres' minimisation over every node but the first; (nodes (n, 3), Summary)."""
    first = nodes[:1]

    def full(free):
        return np.vstack((first, free.reshape(-1, 3)))

    def plus(free, delta):
        moved = (free + delta).reshape(-1, 3)
        moved[:, 2] = wrap(moved[:, 2])
        return moved.reshape(-1)

    def residuals(free):
        return residuals_and_jacobian(full(free), edges, jacobian=False)[0]

    def jacobian(free):
        return residuals_and_jacobian(full(free), edges)[1][:, 3:]

    free, summary = minimize(nodes[1:].reshape(-1).copy(), residuals, jacobian, plus,
                             options or CeresOptions())
    return full(free), summary


def residuals_and_jacobian(x, edges, jacobian: bool = True):
    """Weighted residuals (3m,) and their sparse Jacobian (3m × 3n) at poses ``x`` (n, 3)."""
    src, dst, diff, sqrt_info = edges
    xa, xb = x[src], x[dst]
    c, s = np.cos(xa[:, 2]), np.sin(xa[:, 2])
    dx, dy = xb[:, 0] - xa[:, 0], xb[:, 1] - xa[:, 1]
    raw = np.column_stack((c * dx + s * dy - diff[:, 0], -s * dx + c * dy - diff[:, 1],
                           wrap(xb[:, 2] - xa[:, 2] - diff[:, 2])))
    residual = np.einsum("kij,kj->ki", sqrt_info, raw).reshape(-1)
    if not jacobian:
        return residual, None
    m = len(src)
    block_a = np.zeros((m, 3, 3))
    block_a[:, 0, 0], block_a[:, 0, 1], block_a[:, 0, 2] = -c, -s, -s * dx + c * dy
    block_a[:, 1, 0], block_a[:, 1, 1], block_a[:, 1, 2] = s, -c, -c * dx - s * dy
    block_a[:, 2, 2] = -1.0
    block_b = np.zeros((m, 3, 3))
    block_b[:, 0, 0], block_b[:, 0, 1] = c, s
    block_b[:, 1, 0], block_b[:, 1, 1] = -s, c
    block_b[:, 2, 2] = 1.0
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
