"""Reference motion of the whole-body QP (``wbc.WholeBodyQP``): a trajectory's forward kinematics per frame.

``motion_reference`` samples a reference trajectory (``qpos``, ``qvel``, ``qacc`` per frame) into what
the QP's tasks compare the state with: the whole-body COM and its velocity and acceleration, and per
task body its pose, velocity and acceleration (world frame). ``_body_jac`` is the body Jacobian and its
time derivative (MuJoCo's ``mj_jac`` and ``mj_jacDot``) that both the reference and the QP use.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import mujoco
import numpy as np

__all__ = ["MotionReference", "motion_reference"]


@dataclass
class MotionReference:
    """Reference motion sampled per frame: generalised coordinates and the tasks' body quantities."""

    qpos: np.ndarray  # (F, nq)
    qvel: np.ndarray  # (F, nv)
    qacc: np.ndarray  # (F, nv)
    com: np.ndarray  # (F, 3)
    com_vel: np.ndarray
    com_acc: np.ndarray
    body_pos: dict[str, np.ndarray] = field(default_factory=dict)  # (F, 3) world
    body_quat: dict[str, np.ndarray] = field(default_factory=dict)  # (F, 4) w x y z
    body_vel: dict[str, np.ndarray] = field(default_factory=dict)  # (F, 6) linear, angular (world)
    body_acc: dict[str, np.ndarray] = field(default_factory=dict)  # (F, 6)

    @property
    def frames(self) -> int:
        return len(self.qpos)


def _body_jac(model, data, body: int, point: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(6, nv) Jacobian (linear of ``point`` or the body origin, angular; world) and its time derivative."""
    p = data.xpos[body] if point is None else point
    j, jd = np.zeros((6, model.nv)), np.zeros((6, model.nv))
    mujoco.mj_jac(model, data, j[:3], j[3:], p, body)
    mujoco.mj_jacDot(model, data, jd[:3], jd[3:], p, body)
    return j, jd


def motion_reference(
    model: mujoco.MjModel,
    qpos: np.ndarray,
    qvel: np.ndarray,
    qacc: np.ndarray,
    bodies: tuple[str, ...],
    dt: float,
) -> MotionReference:
    """Forward kinematics of a reference trajectory (``dt``: its frame period [s]): the COM and its
    rates (velocity ``J_com v``, acceleration by central differences), and per body the pose, velocity
    ``J v`` and acceleration ``J a + Jdot v``."""
    data = mujoco.MjData(model)
    n = len(qpos)
    ref = MotionReference(qpos, qvel, qacc, np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3)))
    ids = {b: model.body(b).id for b in bodies}
    for b in bodies:
        ref.body_pos[b], ref.body_quat[b] = np.zeros((n, 3)), np.zeros((n, 4))
        ref.body_vel[b], ref.body_acc[b] = np.zeros((n, 6)), np.zeros((n, 6))
    jc = np.zeros((3, model.nv))
    for f in range(n):
        data.qpos[:], data.qvel[:] = qpos[f], qvel[f]
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        mujoco.mj_comVel(model, data)
        ref.com[f] = data.subtree_com[1]
        mujoco.mj_jacSubtreeCom(model, data, jc, 1)
        ref.com_vel[f] = jc @ qvel[f]
        for b, i in ids.items():
            j, jd = _body_jac(model, data, i)
            ref.body_pos[b][f], ref.body_quat[b][f] = data.xpos[i], data.xquat[i]
            ref.body_vel[b][f] = j @ qvel[f]
            ref.body_acc[b][f] = j @ qacc[f] + jd @ qvel[f]
    if n >= 3:
        ref.com_acc[1:-1] = (ref.com_vel[2:] - ref.com_vel[:-2]) / (2 * dt)
        ref.com_acc[0], ref.com_acc[-1] = ref.com_acc[1], ref.com_acc[-2]
    return ref
