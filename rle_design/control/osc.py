"""Operational-space control of one arm on MuJoCo Jacobians (``mj_jacSite``).

Per physics step the controller reads the tool site's pose and velocity and commands joint torques

    tau = J^T Lambda (Kp e - Kd J dq) + b(q, dq) + (I - J^T Jbar^T) M (Kn (q_home - q) - Dn dq)

where ``e`` stacks the position error [m] and the orientation error (rotation vector of
``q_target q_site^-1``, world frame) [rad], ``Lambda = (J M^-1 J^T)^-1`` is the task-space inertia
[kg, kg m^2], ``Jbar = M^-1 J^T Lambda``, ``b`` MuJoCo's bias forces (gravity, Coriolis;
``qfrc_bias``), the last term a null-space pull towards the home posture; torques are clipped to
the motors' ``ctrlrange``. ``Kd = 2 sqrt(Kp)`` (critical damping of the decoupled task dynamics).
M is the arm's 7x7 block of the joint-space inertia (the gripper's slide joints are ignored).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.scene.elements import element_id

__all__ = ["OscGains", "OperationalSpaceController", "orientation_error"]


@dataclass(frozen=True)
class OscGains:
    """Gains of ``OperationalSpaceController``.

    Attributes:
        kp_pos: Position stiffness per unit task inertia [1/s^2].
        kp_rot: Orientation stiffness per unit task inertia [1/s^2].
        kp_null: Null-space posture stiffness [1/s^2].
        singular_eps: Regularisation of the task-space inertia inverse [1].
    """

    kp_pos: float = 400.0
    kp_rot: float = 300.0
    kp_null: float = 20.0
    singular_eps: float = 1e-4


def _indexer(indices: np.ndarray) -> slice | np.ndarray:
    """A slice where the indices are consecutive (a view: faster than fancy indexing, same values),
    else the index array."""
    idx = np.asarray(indices, dtype=int)
    if idx.size and np.array_equal(idx, np.arange(idx[0], idx[0] + idx.size)):
        return slice(int(idx[0]), int(idx[0]) + int(idx.size))
    return idx


def orientation_error(target_quat: np.ndarray, current_quat: np.ndarray) -> np.ndarray:
    """Rotation vector [rad] (world frame) that turns ``current_quat`` into ``target_quat`` (w, x, y, z)."""
    inv = np.zeros(4)
    mujoco.mju_negQuat(inv, current_quat)
    err = np.zeros(4)
    mujoco.mju_mulQuat(err, target_quat, inv)
    if err[0] < 0:
        err = -err
    vel = np.zeros(3)
    mujoco.mju_quat2Vel(vel, err, 1.0)
    return vel


class OperationalSpaceController:
    """Torques that drive one arm's tool site to a target pose.

    Args:
        model: Compiled model.
        site: Tool site tracked.
        joints: The arm's hinge joints, base to tool.
        motors: One torque motor per joint, same order.
        home: Null-space posture [rad], one per joint.
        gains: Controller gains.

    Raises:
        MissingElement: A site, joint or motor is not in the model (lists the alternatives).
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        site: str,
        joints: tuple[str, ...],
        motors: tuple[str, ...],
        home: tuple[float, ...],
        gains: OscGains = OscGains(),
    ) -> None:
        self.model = model
        self.site = element_id(model, "site", site)
        jids = [element_id(model, "joint", j) for j in joints]
        self.dof = np.array([model.jnt_dofadr[j] for j in jids])
        self.qadr = np.array([model.jnt_qposadr[j] for j in jids])
        self.motors = np.array([element_id(model, "actuator", a) for a in motors])
        self.limits = model.actuator_ctrlrange[self.motors].copy()
        self._lo, self._hi = self.limits[:, 0].copy(), self.limits[:, 1].copy()
        self._dof_s, self._qadr_s = _indexer(self.dof), _indexer(self.qadr)
        self._quat, self._inv, self._qerr = np.zeros(4), np.zeros(4), np.zeros(4)
        self._vel, self._err = np.zeros(3), np.zeros(6)
        self._ix = np.ix_(self.dof, self.dof)
        self._kd_null = 2.0 * np.sqrt(gains.kp_null)
        self.home = np.asarray(home, dtype=float)
        self.gains = gains
        self.kp = np.array([gains.kp_pos] * 3 + [gains.kp_rot] * 3)
        self.kd = 2.0 * np.sqrt(self.kp)
        self._jacp = np.zeros((3, model.nv))
        self._jacr = np.zeros((3, model.nv))
        self._mass = np.zeros((model.nv, model.nv))
        self._eye = np.eye(len(self.dof))
        self._eps6 = gains.singular_eps * np.eye(6)
        self._jac: np.ndarray | None = None

    def site_pose(self, data: mujoco.MjData) -> tuple[np.ndarray, np.ndarray]:
        """(position [m], quaternion (w, x, y, z)) of the tool site in the world frame."""
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, data.site_xmat[self.site])
        return data.site_xpos[self.site].copy(), quat

    def refresh(self, data: mujoco.MjData) -> None:
        """Recompute the configuration-dependent matrices (J, Lambda, the null-space projector, M)."""
        mujoco.mj_jacSite(self.model, data, self._jacp, self._jacr, self.site)
        jac = np.vstack([self._jacp[:, self.dof], self._jacr[:, self.dof]])
        mujoco.mj_fullM(self.model, data, self._mass)
        mass = self._mass[self._ix]
        minv = np.linalg.inv(mass)
        lam = np.linalg.inv(jac @ minv @ jac.T + self._eps6)
        self._jac, self._arm_mass = jac, mass
        self._jt_lam = jac.T @ lam
        self._proj = self._eye - jac.T @ (minv @ self._jt_lam).T

    def torques(
        self, data: mujoco.MjData, target_pos: np.ndarray, target_quat: np.ndarray, refresh: bool = True
    ) -> np.ndarray:
        """Motor torques [N m] for the current state (``mj_forward`` or ``mj_step1`` quantities).

        With ``refresh=False`` the matrices of the last ``refresh`` are reused (the errors, velocities
        and bias forces are always current); they change little within a few milliseconds.
        """
        if refresh or self._jac is None:
            self.refresh(data)
        # the same arithmetic as ``site_pose`` and ``orientation_error``, in preallocated buffers
        quat, inv, qerr, err = self._quat, self._inv, self._qerr, self._err
        mujoco.mju_mat2Quat(quat, data.site_xmat[self.site])
        np.subtract(target_pos, data.site_xpos[self.site], out=err[:3])
        mujoco.mju_negQuat(inv, quat)
        mujoco.mju_mulQuat(qerr, np.asarray(target_quat, dtype=float), inv)
        if qerr[0] < 0:
            np.negative(qerr, out=qerr)
        mujoco.mju_quat2Vel(self._vel, qerr, 1.0)
        err[3:] = self._vel
        dq = data.qvel[self._dof_s]
        acc = self.kp * err - self.kd * (self._jac @ dq)
        tau = self._jt_lam @ acc + data.qfrc_bias[self._dof_s]
        kn = self.gains.kp_null
        posture = self._arm_mass @ (kn * (self.home - data.qpos[self._qadr_s]) - self._kd_null * dq)
        tau += self._proj @ posture
        return np.minimum(np.maximum(tau, self._lo), self._hi)  # np.clip's values, without its overhead

    def apply(
        self, data: mujoco.MjData, target_pos: np.ndarray, target_quat: np.ndarray, refresh: bool = True
    ) -> None:
        """Write ``torques`` into ``data.ctrl`` of the arm's motors."""
        data.ctrl[self.motors] = self.torques(data, target_pos, target_quat, refresh)
