"""Ceres 2.1's trust-region minimiser with its Levenberg–Marquardt strategy, as slam_toolbox's
Ceres solver configures it (solvers/ceres_solver.cpp): Jacobi column scaling fixed at the start
point, the LM diagonal (squared column norms clamped to [min_lm_diagonal, max_lm_diagonal])
divided by the radius, radius updates from the step quality, non-monotonic steps judged against
a reference cost, and Ceres' order of stopping tests (parameter, then function tolerance on the
candidate, which is then not taken; gradient tolerance, iterations and radius after each step).
The result is the lowest-cost accepted point, as Ceres writes back to the parameter blocks.

The problem is given as callables on a flat parameter vector ``x`` (n,): ``residuals(x)`` (m,),
``jacobian(x)`` (sparse m × n) and ``plus(x, delta)`` (Ceres' ``Plus``, e.g. angles wrapped).
The linear system (JᵀJ + D²) δ = −Jᵀr is solved with a sparse LU of scipy on the scaled problem.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve


@dataclasses.dataclass(frozen=True)
class CeresOptions:
    """The Solver::Options slam_toolbox sets (Ceres defaults where it sets none)."""
    max_num_iterations: int = 50
    function_tolerance: float = 1e-3
    gradient_tolerance: float = 1e-6
    parameter_tolerance: float = 1e-3
    min_relative_decrease: float = 1e-3
    initial_trust_region_radius: float = 1e4
    max_trust_region_radius: float = 1e8
    min_trust_region_radius: float = 1e-16
    min_lm_diagonal: float = 1e-6
    max_lm_diagonal: float = 1e32
    max_num_consecutive_invalid_steps: int = 3
    use_nonmonotonic_steps: bool = True
    max_consecutive_nonmonotonic_steps: int = 3
    jacobi_scaling: bool = True


@dataclasses.dataclass
class Summary:
    """What one solve did: Ceres' termination (CONVERGENCE, NO_CONVERGENCE, FAILURE), the reason,
    iterations (as Ceres counts them), successful steps, initial and final cost (½‖r‖²)."""
    termination: str = "NO_CONVERGENCE"
    message: str = ""
    iterations: int = 0
    successful_steps: int = 0
    initial_cost: float = 0.0
    final_cost: float = 0.0

    def usable(self) -> bool:
        """Ceres' IsSolutionUsable: anything but FAILURE."""
        return self.termination != "FAILURE"


class LevenbergMarquardt:
    """LevenbergMarquardtStrategy: the radius, its decrease factor and the cached diagonal."""

    def __init__(self, options: CeresOptions):
        self.o = options
        self.radius = options.initial_trust_region_radius
        self.decrease_factor = 2.0
        self.diagonal = None
        self.reuse_diagonal = False

    def step(self, jac, residual) -> np.ndarray | None:
        """The step δ minimising ‖Jδ + r‖² + ‖Dδ‖² (None when the solve fails)."""
        if not self.reuse_diagonal:
            column_norms = np.asarray(jac.multiply(jac).sum(axis=0)).ravel()
            self.diagonal = np.clip(column_norms, self.o.min_lm_diagonal, self.o.max_lm_diagonal)
        self.reuse_diagonal = True
        normal = (jac.T @ jac).tocsc() + sp.diags(self.diagonal / self.radius, format="csc")
        step = spsolve(normal, -(jac.T @ residual))
        return step if np.all(np.isfinite(step)) else None

    def accepted(self, quality: float) -> None:
        self.radius /= max(1.0 / 3.0, 1.0 - (2.0 * quality - 1.0) ** 3)
        self.radius = min(self.o.max_trust_region_radius, self.radius)
        self.decrease_factor = 2.0
        self.reuse_diagonal = False

    def rejected(self) -> None:
        self.radius /= self.decrease_factor
        self.decrease_factor *= 2.0
        self.reuse_diagonal = True


class StepEvaluator:
    """TrustRegionStepEvaluator: step quality against the current and a reference cost
    (non-monotonic steps, Conn, Gould & Toint algorithm 10.1.2)."""

    def __init__(self, cost: float, max_nonmonotonic: int):
        self.max_nonmonotonic = max_nonmonotonic
        self.minimum = self.current = self.reference = self.candidate = cost
        self.reference_model_change = self.candidate_model_change = 0.0
        self.nonmonotonic = 0

    def quality(self, cost: float, model_change: float) -> float:
        if not math.isfinite(cost):
            return -math.inf
        relative = (self.current - cost) / model_change
        historical = (self.reference - cost) / (self.reference_model_change + model_change)
        return max(relative, historical)

    def accepted(self, cost: float, model_change: float) -> None:
        self.current = cost
        self.candidate_model_change += model_change
        self.reference_model_change += model_change
        if cost < self.minimum:
            self.minimum, self.candidate = cost, cost
            self.nonmonotonic = 0
            self.candidate_model_change = 0.0
        else:
            self.nonmonotonic += 1
            if cost > self.candidate:
                self.candidate = cost
                self.candidate_model_change = 0.0
        if self.nonmonotonic == self.max_nonmonotonic:
            self.reference = self.candidate
            self.reference_model_change = self.candidate_model_change


class _State:
    """The minimiser's current point: x, its residuals, scaled Jacobian, cost, gradient norm."""

    def __init__(self, x, residual, scaled_jac, gradient_max_norm, norm):
        self.x, self.residual, self.jac = x, residual, scaled_jac
        self.cost = 0.5 * float(residual @ residual)
        self.gradient_max_norm = gradient_max_norm
        self.norm = norm


def minimize(x0, residuals, jacobian, plus, options: CeresOptions | None = None):
    """Ceres' TrustRegionMinimizer::Minimize from ``x0``; (best x, Summary)."""
    o = options or CeresOptions()
    jac0 = jacobian(x0)
    scaling = np.ones(len(x0))
    if o.jacobi_scaling:
        scaling = 1.0 / (1.0 + np.sqrt(np.asarray(jac0.multiply(jac0).sum(axis=0)).ravel()))
    scale = sp.diags(scaling, format="csc")

    def state_at(x, residual, jac, norm):
        gradient = jac.T @ residual
        projected = plus(x, -gradient)
        return _State(x, residual, (jac @ scale).tocsr(), float(np.max(np.abs(x - projected),
                                                                         initial=0.0)), norm)

    # x_norm_ is invalid (−1) until the first accepted step, as Ceres leaves it
    current = state_at(np.array(x0, float), residuals(x0), jac0, -1.0)
    summary = Summary(initial_cost=current.cost)
    best_x, best_cost = current.x, current.cost
    strategy = LevenbergMarquardt(o)
    evaluator = StepEvaluator(current.cost, o.max_consecutive_nonmonotonic_steps
                              if o.use_nonmonotonic_steps else 0)
    invalid_steps, iteration, successful = 0, 0, True
    while True:
        if successful:
            summary.successful_steps += 1
            if current.cost < best_cost or iteration == 0:
                best_x, best_cost = current.x, current.cost
        stop = _stop_after_iteration(iteration, successful, current, strategy.radius, o)
        if stop:
            summary.termination, summary.message = stop
            break
        iteration += 1
        successful = False
        step = strategy.step(current.jac, current.residual)
        model_change = -1.0
        if step is not None:
            model_residual = current.jac @ step
            model_change = -float(model_residual @ (current.residual + model_residual / 2.0))
        if model_change <= 0.0:  # invalid step (also a failed linear solve)
            invalid_steps += 1
            if invalid_steps >= o.max_num_consecutive_invalid_steps:
                summary.termination, summary.message = "FAILURE", "consecutive invalid steps"
                break
            strategy.rejected()
            continue
        invalid_steps = 0
        candidate = plus(current.x, step * scaling)
        candidate_residual = residuals(candidate)
        candidate_cost = 0.5 * float(candidate_residual @ candidate_residual)
        if not math.isfinite(candidate_cost):
            candidate_cost = math.inf
        stop = _stop_on_candidate(current, candidate, candidate_cost, o)
        if stop:
            summary.termination, summary.message = stop
            break
        quality = evaluator.quality(candidate_cost, model_change)
        if quality > o.min_relative_decrease:
            current = state_at(candidate, candidate_residual, jacobian(candidate),
                               float(np.linalg.norm(candidate)))
            strategy.accepted(quality)
            evaluator.accepted(candidate_cost, model_change)
            successful = True
        else:
            strategy.rejected()
    summary.iterations, summary.final_cost = iteration, best_cost
    return best_x, summary


def _stop_after_iteration(iteration, successful, current, radius, o: CeresOptions):
    """FinalizeIterationAndCheckIfMinimizerCanContinue's tests: (termination, reason) or None."""
    if iteration >= o.max_num_iterations:
        return "NO_CONVERGENCE", "maximum number of iterations"
    if successful and current.gradient_max_norm <= o.gradient_tolerance:
        return "CONVERGENCE", "gradient tolerance"
    if radius <= o.min_trust_region_radius:
        return "CONVERGENCE", "minimum trust region radius"
    return None


def _stop_on_candidate(current, candidate, candidate_cost, o: CeresOptions):
    """The parameter and function tolerance tests on a candidate point (it is not taken)."""
    step_norm = float(np.linalg.norm(current.x - candidate))
    if step_norm <= o.parameter_tolerance * (current.norm + o.parameter_tolerance):
        return "CONVERGENCE", "parameter tolerance"
    if abs(current.cost - candidate_cost) <= o.function_tolerance * current.cost:
        return "CONVERGENCE", "function tolerance"
    return None
