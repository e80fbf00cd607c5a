"""Public analysis helpers of 09-gello (copied into the agent's workspace as ``gello_helpers.py``).

Nominal dynamics of a leader file: Pinocchio model, springs, residual torque maps over workspace grids,
the holding-torque probe model, and the home poses. Everything here is public: the hidden device
copies differ from the nominal leader only by link-mass factors and a handle payload.
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np

from rle_design.kinematics import (
    GravityMap,
    KinematicModel,
    model_from_mujoco,
    spring_torque,
    springs_from_mujoco,
)
from rle_design.scene import arm_ids, robot_constants

HOME: dict[str, tuple[float, ...]] = {robot: robot_constants(robot).home for robot in arm_ids()}
"""Home pose of each leader [rad], its follower's ``home`` keyframe (a leader mirrors its follower joint
for joint): the first of the 16 probes is always measured here."""
GRID_SEED = 20261122
PUBLIC_GRID_SIZE = 256
"""Poses of the public workspace grid on which the verifier checks spring paths (``contract.spring_path``)."""
LIMIT_MARGIN = 0.1
"""Test and grid poses stay this far inside the joint limits [rad]."""
PROBE_FRICTION_BAND = 0.5
"""Probe torque error: uniform within +-PROBE_FRICTION_BAND x the joint frictionloss (static friction)."""
PROBE_NOISE = 0.002
"""... plus Gaussian current-sensing noise of this standard deviation [N m]."""


def workspace_grid(ranges: np.ndarray, n: int, seed: int = GRID_SEED) -> np.ndarray:
    """``n`` poses uniformly inside the joint ranges (less ``LIMIT_MARGIN``), shape (n, dof) [rad]."""
    ranges = np.asarray(ranges, float)
    rng = np.random.default_rng(seed)
    return rng.uniform(ranges[:, 0] + LIMIT_MARGIN, ranges[:, 1] - LIMIT_MARGIN, size=(n, len(ranges)))


def load_leader(path: str | Path) -> tuple[mujoco.MjModel, KinematicModel, list]:
    """Compiled model, Pinocchio model and springs of a (trusted) ``lead.xml``."""
    m = mujoco.MjModel.from_xml_path(str(path))
    km = model_from_mujoco(m)
    return m, km, springs_from_mujoco(m, km)


def residual(km: KinematicModel, springs: list, poses: np.ndarray) -> np.ndarray:
    """Holding torque the servos must supply, r(q) = g(q) - tau_spring(q), shape (N, dof) [N m]."""
    poses = np.atleast_2d(poses)
    r = GravityMap(km)(poses)
    if springs:
        r -= np.array([spring_torque(km, springs, q) for q in poses])
    return r


def peak_torque(km: KinematicModel, springs: list, ranges: np.ndarray, n: int = 4096) -> np.ndarray:
    """Per-joint peak |r| over a workspace grid [N m] (compare with the 0.35 N m servo limit)."""
    return np.abs(residual(km, springs, workspace_grid(ranges, n))).max(axis=0)
