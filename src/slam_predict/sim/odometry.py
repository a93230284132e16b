"""Odometry error models: how the odometry displacement departs from the executed one.

Every model maps the executed body-frame displacement of one step (dx, dy, dθ) (m, m, rad) to
the displacement the odometry integrates. Odometry integrates the *executed* velocity, so it
keeps moving while the robot is stalled against a wall, as in Stage.

Models (``OdomConfig.model``; e = (e_x, e_y, e_θ) from the config or the World):

* ``uniform_per_run`` (default; the thesis' reading of Stage): once per run, each e_i is drawn
  uniformly in [−e_i, +e_i]; then every step dx' = dx·(1+e_x), dy' = dy + e_y·dx (lateral drift,
  m per m travelled), dθ' = dθ·(1+e_θ). After a straight run of L m the odometry is off by
  (e_x·L, e_y·L); after a rotation of Θ rad by e_θ·Θ. Over runs the errors have zero mean and
  std e_i/√3 per unit of travel.
* ``fixed`` (Stage's code, model_position.cc): e used as constant biases, dx' = dx·(1+e_x),
  dy' = dy·(1+e_y), dθ' = dθ·(1+e_θ). For a differential drive dy = 0, so e_y has no effect —
  exactly as in Stage.
* ``none``: odometry = executed motion.
* ``gaussian_per_step`` (random walk, like real wheel odometry): independent zero-mean Gaussian
  noise per step with variances k_x²·|Δs|, k_y²·|Δs| on dx, dy and k_θθ²·|dθ| + k_θs²·|Δs| on dθ
  (Δs = step length in m). Errors grow like √distance: std k_x·√L after L m, k_θθ·√Θ after a
  rotation of Θ rad. Defaults (0.005 m/√m, 0.005 m/√m, 0.01 rad/√rad, 0.002 rad/√m).
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from slam_predict.sim.config import OdomConfig

Delta = tuple[float, float, float]


class OdometryModel:
    """Base class: identity (the ``none`` model)."""

    name = "none"
    _bias: tuple[float, ...] = (0.0, 0.0, 0.0)

    def perturb(self, delta: Delta, rng: np.random.Generator) -> Delta:
        """The odometry displacement for the executed body-frame ``delta`` of one step."""
        return delta

    @property
    def bias(self) -> tuple[float, float, float]:
        """Constant proportional errors (e_x, e_y, e_θ) in use this run (zeros if none)."""
        return self._bias  # type: ignore[return-value]

    def metadata(self) -> dict[str, Any]:
        """A JSON-ready description of the model and the errors in use."""
        return {"model": self.name, "bias": list(self.bias)}


class UniformPerRun(OdometryModel):
    """Per-run proportional errors drawn uniformly in [−bound, +bound]; lateral drift on y."""

    name = "uniform_per_run"

    def __init__(self, bound: Sequence[float], rng: np.random.Generator):
        self.bound = tuple(float(b) for b in bound)
        self._bias = tuple(float(v) for v in rng.uniform(-1.0, 1.0, 3) * np.asarray(self.bound))

    def perturb(self, delta: Delta, rng: np.random.Generator) -> Delta:
        dx, dy, dth = delta
        ex, ey, eth = self._bias
        return dx * (1.0 + ex), dy + ey * dx, dth * (1.0 + eth)

    def metadata(self) -> dict[str, Any]:
        return {"model": self.name, "bias": list(self.bias), "bound": list(self.bound)}


class FixedBias(OdometryModel):
    """Stage's code: constant multiplicative biases (1 + e) on each body-frame axis."""

    name = "fixed"

    def __init__(self, bias: Sequence[float]):
        self._bias = tuple(float(b) for b in bias)

    def perturb(self, delta: Delta, rng: np.random.Generator) -> Delta:
        dx, dy, dth = delta
        ex, ey, eth = self._bias
        return dx * (1.0 + ex), dy * (1.0 + ey), dth * (1.0 + eth)


class GaussianPerStep(OdometryModel):
    """Random-walk noise: per-step Gaussian with variance proportional to distance/rotation."""

    name = "gaussian_per_step"

    def __init__(self, densities: Sequence[float]):
        self.k_x, self.k_y, self.k_thth, self.k_ths = (float(k) for k in densities)

    def perturb(self, delta: Delta, rng: np.random.Generator) -> Delta:
        dx, dy, dth = delta
        ds = math.hypot(dx, dy)
        if ds == 0.0 and dth == 0.0:
            return delta
        std_th = math.sqrt(self.k_thth ** 2 * abs(dth) + self.k_ths ** 2 * ds)
        n = rng.standard_normal(3)
        sq = math.sqrt(ds)
        return (dx + self.k_x * sq * n[0], dy + self.k_y * sq * n[1], dth + std_th * n[2])

    def metadata(self) -> dict[str, Any]:
        return {"model": self.name, "bias": [0.0, 0.0, 0.0],
                "gaussian": [self.k_x, self.k_y, self.k_thth, self.k_ths]}


def world_error(odom_error: Sequence[float]) -> tuple[float, float, float]:
    """(e_x, e_y, e_θ) from a World's 4-element odom_error (x, y, z, yaw rad); z is unused."""
    values = tuple(float(v) for v in odom_error)
    if len(values) == 4:
        return values[0], values[1], values[3]
    if len(values) == 3:
        return values  # type: ignore[return-value]
    raise ValueError(f"odom_error needs 3 or 4 values, got {len(values)}")


def make_odometry(config: OdomConfig, default_error: Sequence[float],
                  rng: np.random.Generator) -> OdometryModel:
    """The model named in ``config``; e = ``config.error`` or else ``default_error``.

    ``uniform_per_run`` draws its errors from ``rng`` here (three uniforms), once per run.
    """
    error = tuple(config.error) if config.error is not None else tuple(default_error)
    if config.model == "uniform_per_run":
        return UniformPerRun([abs(e) for e in error], rng)
    if config.model == "fixed":
        return FixedBias(error)
    if config.model == "gaussian_per_step":
        return GaussianPerStep(config.gaussian)
    if config.model == "none":
        return OdometryModel()
    raise ValueError(f"unknown odometry model '{config.model}'")
