"""Passive torque of joint springs, tendon springs and counterweights (what Pinocchio drops).

Sign convention: the returned torque is the passive generalized force the springs apply to the joints
(MuJoCo's ``qfrc_spring``/``qfrc_passive`` at rest). The residual a servo must supply to hold pose q
is ``r(q) = g(q) - tau_spring(q)``.

Models (MuJoCo semantics):

* joint spring: ``tau = -k (q - springref)``;
* tendon spring with ``springlength = (lo, hi)``: force ``f = -k (L - hi)`` for L > hi,
  ``-k (L - lo)`` for L < lo, 0 in between (``(0, 0)`` is an ideal zero-length spring,
  ``(0, L0)`` a tension-only spring of free length L0); ``tau = (dL/dq)^T f``. Spatial tendons are
  straight segments between sites; fixed tendons have ``L = sum coef_j q_j``.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
import pinocchio as pin

from rle_design.errors import MjcfError
from rle_design.kinematics.model import KinematicModel

__all__ = [
    "JointSpring",
    "TendonSpring",
    "counterweight_moment",
    "spring_torque",
    "springs_from_mujoco",
    "tendon_length",
    "torsion_spring_residual",
    "zero_length_spring_residual",
    "zero_length_spring_torque",
]


@dataclass(frozen=True)
class JointSpring:
    """Torsion spring on one joint.

    Attributes:
        index: Coordinate index in q.
        stiffness: k [N m/rad].
        springref: Rest angle [rad].
    """

    index: int
    stiffness: float
    springref: float


@dataclass(frozen=True)
class TendonSpring:
    """Spring along a tendon.

    Attributes:
        name: Tendon name.
        stiffness: k [N/m] (spatial) or [N m/rad] (fixed).
        lengthspring: Dead band ``(lo, hi)`` of zero force [m].
        points: Spatial path: ``(pinocchio joint id, point in that joint frame [m])`` per site.
        coef: Fixed tendon: ``(q index, coefficient)`` pairs.
    """

    name: str
    stiffness: float
    lengthspring: tuple[float, float]
    points: tuple[tuple[int, tuple[float, float, float]], ...] = ()
    coef: tuple[tuple[int, float], ...] = ()


def springs_from_mujoco(m: mujoco.MjModel, km: KinematicModel) -> list[JointSpring | TendonSpring]:
    """Springs of a compiled model expressed on the Pinocchio model.

    Raises:
        MjcfError: A stiff tendon wraps around a geom or uses a pulley (code ``kinematics.tendon_wrap``).
    """
    springs: list[JointSpring | TendonSpring] = []
    qindex = {j: k for k, j in enumerate(km.mj_joint_ids)}
    for j in range(m.njnt):
        if m.jnt_stiffness[j] != 0.0:
            springs.append(
                JointSpring(qindex[j], float(m.jnt_stiffness[j]), float(m.qpos_spring[m.jnt_qposadr[j]]))
            )
    if m.ntendon == 0:
        return springs
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)
    q0 = np.array([m.qpos0[m.jnt_qposadr[j]] for j in km.mj_joint_ids])
    pin.forwardKinematics(km.model, km.data, q0)
    body_joint = _body_to_pin_joint(m, km)
    for t in range(m.ntendon):
        k = float(m.tendon_stiffness[t])
        if k == 0.0:
            continue
        name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_TENDON, t) or f"tendon{t}"
        adr, num = int(m.tendon_adr[t]), int(m.tendon_num[t])
        types = [int(m.wrap_type[w]) for w in range(adr, adr + num)]
        ls = (float(m.tendon_lengthspring[t, 0]), float(m.tendon_lengthspring[t, 1]))
        if all(ty == mujoco.mjtWrap.mjWRAP_JOINT for ty in types):
            coef = tuple((qindex[int(m.wrap_objid[w])], float(m.wrap_prm[w])) for w in range(adr, adr + num))
            springs.append(TendonSpring(name, k, ls, coef=coef))
            continue
        if any(ty != mujoco.mjtWrap.mjWRAP_SITE for ty in types):
            raise MjcfError(
                f"stiff tendon '{name}' wraps around geoms or uses pulleys; only straight site-to-site "
                "spatial tendons and fixed tendons have an analytic spring model",
                code="kinematics.tendon_wrap",
                element="spatial",
            )
        pts = []
        for w in range(adr, adr + num):
            sid = int(m.wrap_objid[w])
            jid = body_joint[int(m.site_bodyid[sid])]
            oMi = km.data.oMi[jid]
            local = oMi.rotation.T @ (d.site_xpos[sid] - oMi.translation)
            pts.append((jid, tuple(float(x) for x in local)))
        springs.append(TendonSpring(name, k, ls, points=tuple(pts)))
    return springs


def _body_to_pin_joint(m: mujoco.MjModel, km: KinematicModel) -> dict[int, int]:
    """Pinocchio joint id carrying each MuJoCo body (0 = universe)."""
    pin_of_mj = {j: k + 1 for k, j in enumerate(km.mj_joint_ids)}
    out = {0: 0}
    for b in range(1, m.nbody):
        if m.body_jntnum[b] > 0:
            out[b] = pin_of_mj[int(m.body_jntadr[b] + m.body_jntnum[b] - 1)]
        else:
            out[b] = out[int(m.body_parentid[b])]
    return out


def _spatial(km: KinematicModel, sp: TendonSpring, q: np.ndarray) -> tuple[float, np.ndarray]:
    """Length [m] and dL/dq of a site-to-site tendon (kinematics already computed at q)."""
    model, data = km.model, km.data
    pts, jacs = [], []
    for jid, local in sp.points:
        oMi = data.oMi[jid]
        p = oMi.translation + oMi.rotation @ np.asarray(local)
        if jid == 0:
            jac = np.zeros((3, model.nv))
        else:
            j6 = np.reshape(pin.getJointJacobian(model, data, jid, pin.LOCAL_WORLD_ALIGNED), (6, model.nv))
            jac = j6[:3] - np.cross(p - oMi.translation, j6[3:].T).T
        pts.append(p)
        jacs.append(jac)
    length, grad = 0.0, np.zeros(model.nv)
    for a in range(len(pts) - 1):
        seg = pts[a + 1] - pts[a]
        ln = float(np.linalg.norm(seg))
        length += ln
        if ln > 1e-12:
            grad += (seg / ln) @ (jacs[a + 1] - jacs[a])
    return length, grad


def _force(sp: TendonSpring, length: float) -> float:
    lo, hi = sp.lengthspring
    if length > hi:
        return -sp.stiffness * (length - hi)
    if length < lo:
        return -sp.stiffness * (length - lo)
    return 0.0


def tendon_length(km: KinematicModel, sp: TendonSpring, q: np.ndarray) -> float:
    """Tendon length at pose q [m]."""
    q = np.asarray(q, float)
    if sp.coef:
        return float(sum(c * q[i] for i, c in sp.coef))
    pin.computeJointJacobians(km.model, km.data, q)
    return _spatial(km, sp, q)[0]


def spring_torque(km: KinematicModel, springs: list[JointSpring | TendonSpring], q: np.ndarray) -> np.ndarray:
    """Passive spring torque at pose q [N m] (MuJoCo ``qfrc_spring`` + tendon springs at rest)."""
    q = np.asarray(q, float)
    tau = np.zeros(km.model.nv)
    spatial = [s for s in springs if isinstance(s, TendonSpring) and s.points]
    if spatial:
        pin.computeJointJacobians(km.model, km.data, q)
    for s in springs:
        if isinstance(s, JointSpring):
            tau[s.index] += -s.stiffness * (q[s.index] - s.springref)
        elif s.coef:
            length = sum(c * q[i] for i, c in s.coef)
            f = _force(s, length)
            for i, c in s.coef:
                tau[i] += c * f
        else:
            length, grad = _spatial(km, s, q)
            tau += grad * _force(s, length)
    return tau


def zero_length_spring_torque(
    k: float, a: float, b: float, theta: np.ndarray, free_length: float = 0.0, tension_only: bool = False
) -> np.ndarray:
    """Torque of a spring from a point ``a`` above a pivot to a point ``b`` along a link [N m].

    With theta the link angle from the upward vertical, L = sqrt(a^2 + b^2 - 2 a b cos(theta)) and
    tension k (L - L0): tau = k a b sin(theta) (1 - L0 / L), pulling the link towards upright. A
    tension-only spring (cable) carries no force while L < L0.
    """
    theta = np.asarray(theta, float)
    length = np.sqrt(a * a + b * b - 2 * a * b * np.cos(theta))
    stretch = 1.0 - free_length / length
    if tension_only:
        stretch = np.maximum(stretch, 0.0)
    return k * a * b * np.sin(theta) * stretch


def zero_length_spring_residual(
    mass: float,
    lever: float,
    k: float,
    a: float,
    b: float,
    theta: np.ndarray,
    free_length: float = 0.0,
    g: float = 9.81,
) -> np.ndarray:
    """Gravity torque minus spring torque of a balanced link [N m]: m g l sin(theta) - tau_spring.

    With k a b = m g l the residual is k a b sin(theta) L0 / L: exactly zero for a zero-length spring.
    """
    return mass * g * lever * np.sin(np.asarray(theta, float)) - zero_length_spring_torque(
        k, a, b, theta, free_length
    )


def torsion_spring_residual(mgl: float, k: float, theta: np.ndarray, theta0: float) -> np.ndarray:
    """Residual m g l sin(theta) - k (theta - theta0) of a torsion-spring balanced link [N m]."""
    theta = np.asarray(theta, float)
    return mgl * np.sin(theta) - k * (theta - theta0)


def counterweight_moment(masses: np.ndarray, levers: np.ndarray) -> float:
    """First moment m_c r_c a counterweight needs to balance links (sum m_i l_i) [kg m]."""
    return float(np.dot(np.asarray(masses, float), np.asarray(levers, float)))
