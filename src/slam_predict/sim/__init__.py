"""The Stage-equivalent simulator: kinematics, odometry error models, laser ray casting.

``Simulator(world, config, rng).step(v, w) -> SimState``; see :mod:`slam_predict.sim.simulator`.
"""
from slam_predict.sim.config import LaserOverrides, OdomConfig, RobotOverrides, SimConfig
from slam_predict.sim.simulator import SimState, Simulator

__all__ = ["Simulator", "SimConfig", "SimState", "OdomConfig", "RobotOverrides",
           "LaserOverrides"]
