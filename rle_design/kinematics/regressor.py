"""Linear-in-parameters gravity regressor and base-parameter reduction.

At rest (v = a = 0) the joint torque is linear in the per-link inertial parameters:
``g(q) = Y_g(q) beta`` with, for every joint, ``beta_j = (m_j, m_j c_jx, m_j c_jy, m_j c_jz)`` (mass and
first moment in the joint frame). ``Y_g`` is the mass/first-moment block of Pinocchio's
``computeJointTorqueRegressor(q, 0, 0)``; the rotational-inertia columns vanish at rest.
Only some combinations of beta are identifiable from torques; ``base_parameters`` finds them by QR
with column pivoting of a stacked regressor over random poses.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin
import scipy.linalg

from rle_design.kinematics.model import KinematicModel

__all__ = [
    "BaseParameters",
    "base_parameters",
    "fit_base",
    "gravity_parameters",
    "gravity_regressor",
    "stacked_regressor",
]


def _columns(nj: int) -> np.ndarray:
    return np.concatenate([10 * j + np.arange(4) for j in range(nj)])


def gravity_regressor(km: KinematicModel, q: np.ndarray) -> np.ndarray:
    """Y_g(q), shape (nv, 4 nv): g(q) = Y_g(q) @ gravity_parameters(km) [N m]."""
    model = km.model
    zero = np.zeros(model.nv)
    y = pin.computeJointTorqueRegressor(model, km.data, np.asarray(q, float), zero, zero)
    y = np.reshape(y, (model.nv, 10 * (model.njoints - 1)))  # 1-row results come back flattened
    return np.array(y[:, _columns(model.njoints - 1)])


def stacked_regressor(km: KinematicModel, poses: np.ndarray) -> np.ndarray:
    """Regressors of several poses stacked vertically, shape (N nv, 4 nv)."""
    return np.vstack([gravity_regressor(km, q) for q in np.atleast_2d(poses)])


def gravity_parameters(km: KinematicModel) -> np.ndarray:
    """Nominal (m, m c) of every joint's rigid body, shape (4 nv,) [kg, kg m]."""
    out = []
    for j in range(1, km.model.njoints):
        inertia = km.model.inertias[j]
        out.extend([inertia.mass, *(inertia.mass * np.asarray(inertia.lever))])
    return np.array(out)


@dataclass(frozen=True)
class BaseParameters:
    """Identifiable combinations of the gravity parameters.

    ``beta_base = beta[independent] + K @ beta[dependent]`` and ``Y beta = Y[:, independent] @ beta_base``.

    Attributes:
        independent: Column indices kept [4 nv indices].
        dependent: Column indices expressed through the kept ones.
        k: Mapping, shape (len(independent), len(dependent)).
        zero: Columns identically zero over the sampled poses (never identifiable).
    """

    independent: np.ndarray
    dependent: np.ndarray
    k: np.ndarray
    zero: np.ndarray

    @property
    def size(self) -> int:
        return int(self.independent.size)

    def project(self, beta: np.ndarray) -> np.ndarray:
        """Base parameters of a full parameter vector."""
        beta = np.asarray(beta, float)
        return beta[self.independent] + self.k @ beta[self.dependent]

    def reduce(self, y: np.ndarray) -> np.ndarray:
        """Base regressor: the kept columns of a full regressor."""
        return np.asarray(y)[:, self.independent]


def base_parameters(
    km: KinematicModel, n_poses: int = 64, seed: int = 0, tol: float = 1e-8
) -> BaseParameters:
    """Base parameters by QR with column pivoting of a stacked regressor at random poses.

    Args:
        km: Model.
        n_poses: Random poses sampled uniformly in [-pi, pi] (joint limits do not change identifiability).
        seed: RNG seed.
        tol: Relative rank tolerance on |R_ii|.
    """
    rng = np.random.default_rng(seed)
    y = stacked_regressor(km, rng.uniform(-np.pi, np.pi, size=(n_poses, km.model.nq)))
    norms = np.linalg.norm(y, axis=0)
    zero = np.flatnonzero(norms <= tol * max(norms.max(), 1e-300))
    live = np.setdiff1d(np.arange(y.shape[1]), zero)
    _, r, piv = scipy.linalg.qr(y[:, live], mode="economic", pivoting=True)
    diag = np.abs(np.diag(r))
    rank = int(np.sum(diag > tol * diag[0]))
    indep = live[piv[:rank]]
    dep_local = piv[rank:]
    k = (
        scipy.linalg.solve_triangular(r[:rank, :rank], r[:rank, rank:])
        if dep_local.size
        else np.zeros((rank, 0))
    )
    order = np.argsort(indep)
    return BaseParameters(indep[order], live[dep_local], k[order], zero)


def fit_base(
    y_base: np.ndarray,
    tau: np.ndarray,
    prior: np.ndarray | None = None,
    ridge: float = 0.0,
) -> np.ndarray:
    """Least squares on base parameters with an optional ridge towards a prior.

    Solves min ||Y_b x - tau||^2 + ridge ||x - prior||^2.

    Args:
        y_base: Stacked base regressor, shape (m, p).
        tau: Stacked torques [N m], shape (m,).
        prior: Prior base parameters (default zeros).
        ridge: Tikhonov weight [N^2 m^2 per unit parameter^2].
    """
    y_base = np.asarray(y_base, float)
    p = y_base.shape[1]
    x0 = np.zeros(p) if prior is None else np.asarray(prior, float)
    a = y_base.T @ y_base + ridge * np.eye(p)
    b = y_base.T @ (np.asarray(tau, float) - y_base @ x0)
    return x0 + np.linalg.lstsq(a, b, rcond=None)[0]
