"""Whole-body QP control of a floating-base robot on position servos (MuJoCo dynamics, OSQP).

Each control step solves one QP over ``x = [qdd (nv), lam (nlam) / (m g), tau (nu) / effort]``:

    minimise   sum_i w_i |J_i qdd + Jdot_i v - a_i|^2 + regularisation
    subject to M(q) qdd + h(q, v) = S^T tau + sum_c J_c^T U lam     (floating-base dynamics)
               lam >= 0  (stance contact points),  lam = 0  (swing)  (friction pyramids)
               |tau| <= torque_fraction * effort                     (effort limits)

and ``J_c qdd + Jdot_c v = -kd_c J_c v`` for every stance body (6 rows: the sole at rest).
``U`` holds the four edges ``n +- mu t`` of the linearised friction cone at every contact point of a
stance body (a sole's polygon vertices: the centre of pressure stays on the sole). Tasks: the whole-body
COM, frame tasks (orientation and/or position of named bodies: the anchor, the hands, the pelvis), the
feet (a swing foot tracks its reference pose, a stance foot's acceleration is damped to rest) and a joint
posture. Every task's desired acceleration is ``a_ref + kp (x_ref - x) + kd (v_ref - v)``.

The dynamics are MuJoCo's own (``mj_fullM``, ``qfrc_bias``, ``mj_jac``, ``mj_jacDot``) on a nominal
model the caller passes: the same MJCF the simulator uses with its armature, and the simulator's
free-joint velocity convention (linear world, angular local), so no model conversion can drift from the
simulated plant. The tests cross-check the static torques against Pinocchio's RNEA.

The sparsity pattern of ``P`` and ``A`` is fixed at construction (dense ``qdd`` block, every contact
column of both feet present); a swing foot only gets the bound ``lam = 0``. OSQP is warm-started from
the previous solution. A stance body's acceleration is a hard equality, ``J qdd + Jdot v = -kd J v``
(its rows are free for a swing body). Torques become PD targets of the servos: ``tau = kp (target - q) - kd qd``
averaged over the hold period ``T`` gives ``target = q_m + (tau + kd v_m) / kp`` with the mean state
``q_m = q + v T/2 + qdd T^2/6``, ``v_m = v + qdd T/2`` (``T = 0``: the exact instantaneous form).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import mujoco
import numpy as np
import scipy.sparse as sp

__all__ = [
    "FrameTask",
    "MotionReference",
    "WbcGains",
    "WbcSolution",
    "WholeBodyQP",
    "motion_reference",
    "servo_targets",
]

GRAVITY = 9.81
MAX_QACC = 1e3
"""A solution with a larger generalised acceleration [m/s^2, rad/s^2] is rejected (previous kept)."""
OSQP_SETTINGS = {
    "verbose": False,
    "eps_abs": 1e-5,
    "eps_rel": 1e-5,
    "max_iter": 4000,
    "polishing": False,
    "warm_starting": True,
    "adaptive_rho": True,
    "check_termination": 10,
}


@dataclass(frozen=True)
class FrameTask:
    """A body task: its position (``pos`` weight) and/or orientation (``ori`` weight)."""

    body: str
    pos: float = 0.0
    ori: float = 0.0
    kp: float = 100.0
    kd: float = 20.0
    lead: int = 0
    """Track the reference this many frames ahead (a lag the plant cannot avoid: latency, saturation)."""


@dataclass(frozen=True)
class WbcGains:
    """Weights [1] and gains [1/s^2, 1/s] of the QP's tasks."""

    com: tuple[float, float, float] = (10.0, 10.0, 10.0)
    com_kp: float = 60.0
    com_kd: float = 15.0
    frames: tuple[FrameTask, ...] = ()
    swing_pos: float = 10.0
    swing_ori: float = 5.0
    swing_kp: float = 200.0
    swing_kd: float = 30.0
    contact_kd: float = 10.0
    posture: float = 0.5
    posture_kp: float = 100.0
    posture_kd: float = 20.0
    posture_lead: int = 0
    """Frames ahead the posture reference of ``lead_joints`` (indices into ``joints``) is taken."""
    lead_joints: tuple[int, ...] = ()
    reg_qdd: float = 1e-4
    reg_lam: float = 1e-4
    reg_tau: float = 1e-3
    tau_rate: float = 0.0
    """Weight of |(tau - tau_prev) / effort|^2: smooths the torques (the servo targets) between steps."""
    torque_fraction: float = 0.95


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


def _ori_error(q_ref: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Rotation vector of ``q_ref q^-1`` (world frame) [rad]."""
    d = np.zeros(4)
    mujoco.mju_mulQuat(d, q_ref, np.array([q[0], -q[1], -q[2], -q[3]]))
    e = np.zeros(3)
    mujoco.mju_quat2Vel(e, d, 1.0)
    return e


def _generators(mu: float) -> np.ndarray:
    """(3, 4) edges of the friction pyramid |f_x| + |f_y| <= mu f_z (floor normal z)."""
    return np.array([[mu, -mu, 0, 0], [0, 0, mu, -mu], [1.0, 1.0, 1.0, 1.0]])


@dataclass
class WbcSolution:
    qacc: np.ndarray
    tau: np.ndarray
    forces: dict[str, np.ndarray]  # per contact body: (k, 3) world forces at its points [N]
    status: str
    iterations: int


class WholeBodyQP:
    """The QP controller.

    Args:
        model: Nominal floating-base model (first joint free; no floor needed: contacts are the QP's).
        joints: Actuated hinge joints, in the order of ``tau`` and the servo arrays.
        effort: (nu,) torque limits [N m].
        contacts: Per contact body (the feet, in schedule order), its contact points (k, 3) in the body
            frame (a sole polygon).
        mu: Friction coefficient of the pyramids.
        gains: Task weights and gains.
        reference: The motion to track (``motion_reference``; must include the contact and frame bodies).
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        joints: tuple[str, ...],
        effort: np.ndarray,
        contacts: dict[str, np.ndarray],
        reference: MotionReference,
        *,
        mu: float = 0.6,
        gains: WbcGains | None = None,
        settings: dict | None = None,
    ) -> None:
        self.settings = {**OSQP_SETTINGS, **(settings or {})}
        self.model, self.data = model, mujoco.MjData(model)
        self.g = gains or WbcGains()
        self.ref = reference
        self.nv = model.nv
        self.dofs = np.array([model.jnt_dofadr[model.joint(j).id] for j in joints])
        self.qadr = np.array([model.jnt_qposadr[model.joint(j).id] for j in joints])
        self.nu = len(joints)
        self.effort = np.asarray(effort, dtype=float)
        self.weight = mujoco.mj_getTotalmass(model) * GRAVITY
        self.contact_bodies = list(contacts)
        self.contact_ids = [model.body(b).id for b in contacts]
        self.points = [np.asarray(p, dtype=float) for p in contacts.values()]
        self.U = _generators(mu)
        self.nlam = 4 * sum(len(p) for p in self.points)
        self.frame_ids = {t.body: model.body(t.body).id for t in self.g.frames}
        nv, nl, nu = self.nv, self.nlam, self.nu
        self.n = nv + nl + nu
        # fixed patterns: P upper triangle of the dense qdd block plus diagonals; A dense dynamics rows
        pp = np.zeros((self.n, self.n), bool)
        pp[:nv, :nv] = np.triu(np.ones((nv, nv), bool))
        pp[np.arange(self.n), np.arange(self.n)] = True
        nc = 6 * len(self.contact_ids)
        self.rows = nv + nl + nu + nc
        ap = np.zeros((self.rows, self.n), bool)
        ap[:nv, : nv + nl] = True
        ap[self.dofs, nv + nl + np.arange(nu)] = True
        ap[nv + np.arange(nl + nu), nv + np.arange(nl + nu)] = True
        ap[nv + nl + nu :, :nv] = True  # stance bodies at rest: J qdd = -Jdot v - kd J v
        self._p_idx = self._pattern(pp)
        self._a_idx = self._pattern(ap)
        self._p0, self._a0 = self._csc(pp.astype(float), pp), self._csc(ap.astype(float), ap)
        tf = self.g.torque_fraction
        self.l = np.concatenate([np.zeros(nv), np.zeros(nl), -np.full(nu, tf), np.full(nc, -np.inf)])
        self.u = np.concatenate([np.zeros(nv), np.full(nl, np.inf), np.full(nu, tf), np.full(nc, np.inf)])
        self._l0, self._u0 = self.l.copy(), self.u.copy()
        self.reset()

    def reset(self) -> None:
        """A fresh OSQP solver (no warm start from earlier solves): episodes replay bit for bit."""
        import osqp

        self.l, self.u = self._l0.copy(), self._u0.copy()
        self.solver = osqp.OSQP()
        self.solver.setup(
            self._p0.copy(), np.zeros(self.n), self._a0.copy(), self.l.copy(), self.u.copy(), **self.settings
        )
        self.prev: np.ndarray | None = None

    @staticmethod
    def _pattern(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        cols, rows = np.nonzero(mask.T)  # column-major: CSC order
        return rows, cols

    def _csc(self, dense: np.ndarray, mask: np.ndarray) -> sp.csc_matrix:
        rows, cols = self._pattern(mask)
        return sp.csc_matrix((dense[rows, cols], (rows, cols)), shape=mask.shape)

    # -- one step -------------------------------------------------------------------------------
    def solve(
        self,
        qpos: np.ndarray,
        qvel: np.ndarray,
        frame: int,
        stance: np.ndarray,
        scales: dict[str, float] | None = None,
        offset: np.ndarray | None = None,
        swing: dict[str, tuple] | None = None,
    ) -> WbcSolution:
        """Accelerations, torques and contact forces for the state (``qpos``, ``qvel``) tracking
        reference ``frame``; ``stance[i]``: contact body i may push. ``scales`` multiplies the weights
        of task groups this step: ``com_xy``, ``frames``, ``posture``. ``offset`` (3,) shifts every
        reference position (COM, bodies) [m]; ``swing`` replaces a swing body's reference by ``(pos,
        quat, vel (6), acc (6))`` (a step the reference does not have)."""
        sc = {"com_xy": 1.0, "frames": 1.0, "posture": 1.0, **(scales or {})}
        off = np.zeros(3) if offset is None else np.asarray(offset, dtype=float)
        swing = swing or {}
        m, d, g, r = self.model, self.data, self.g, self.ref
        nv, nl, nu = self.nv, self.nlam, self.nu
        f = min(max(frame, 0), r.frames - 1)
        d.qpos[:], d.qvel[:] = qpos, qvel
        mujoco.mj_forward(m, d)
        M = np.zeros((nv, nv))
        mujoco.mj_fullM(m, d, M)
        h = d.qfrc_bias - d.qfrc_passive
        v = d.qvel
        H, c = np.zeros((nv, nv)), np.zeros(nv)

        def add(j: np.ndarray, a: np.ndarray, w: np.ndarray | float) -> None:
            wj = j * np.reshape(w, (-1, 1)) if np.ndim(w) else j * w
            H[:] += wj.T @ j
            c[:] -= wj.T @ a

        # COM (Jdot v of the COM neglected)
        jc = np.zeros((3, nv))
        mujoco.mj_jacSubtreeCom(m, d, jc, 1)
        com, vcom = d.subtree_com[1].copy(), jc @ v
        a = r.com_acc[f] + g.com_kp * (r.com[f] + off - com) + g.com_kd * (r.com_vel[f] - vcom)
        add(jc, a, np.asarray(g.com) * np.array([sc["com_xy"], sc["com_xy"], 1.0]))
        # frame tasks
        for t in g.frames:
            b = self.frame_ids[t.body]
            j, jd = _body_jac(m, d, b)
            ft = min(f + t.lead, r.frames - 1)
            e = np.concatenate(
                [r.body_pos[t.body][ft] + off - d.xpos[b], _ori_error(r.body_quat[t.body][ft], d.xquat[b])]
            )
            a = r.body_acc[t.body][ft] + t.kp * e + t.kd * (r.body_vel[t.body][ft] - j @ v) - jd @ v
            add(j, a, sc["frames"] * np.array([t.pos] * 3 + [t.ori] * 3))
        # feet: stance damped to rest, swing tracks the reference
        cols = np.zeros((nv, nl))
        A = np.zeros((self.rows, self.n))
        k, r0 = 0, nv + nl + nu
        for i, (name, b) in enumerate(zip(self.contact_bodies, self.contact_ids)):
            j, jd = _body_jac(m, d, b)
            rows = slice(r0 + 6 * i, r0 + 6 * i + 6)
            A[rows, :nv] = j
            if stance[i]:
                self.l[rows] = self.u[rows] = -g.contact_kd * (j @ v) - jd @ v
            else:
                self.l[rows], self.u[rows] = -np.inf, np.inf
                pos, quat, vel, acc = swing.get(
                    name,
                    (
                        r.body_pos[name][f] + off,
                        r.body_quat[name][f],
                        r.body_vel[name][f],
                        r.body_acc[name][f],
                    ),
                )
                e = np.concatenate([pos - d.xpos[b], _ori_error(quat, d.xquat[b])])
                a = acc + g.swing_kp * e + g.swing_kd * (vel - j @ v) - jd @ v
                add(j, a, np.array([g.swing_pos] * 3 + [g.swing_ori] * 3))
            rot = d.xmat[b].reshape(3, 3)
            jp = np.zeros((3, nv))
            for p in self.points[i]:
                mujoco.mj_jac(m, d, jp, None, d.xpos[b] + rot @ p, b)
                cols[:, k : k + 4] = jp.T @ self.U * self.weight
                k += 4
        # posture
        qerr = np.zeros(nv)
        mujoco.mj_differentiatePos(m, qerr, 1.0, qpos, r.qpos[f])
        a = r.qacc[f] + g.posture_kp * qerr + g.posture_kd * (r.qvel[f] - v)
        if g.posture_lead and len(g.lead_joints):
            fl = min(f + g.posture_lead, r.frames - 1)
            ql = np.zeros(nv)
            mujoco.mj_differentiatePos(m, ql, 1.0, qpos, r.qpos[fl])
            lead = r.qacc[fl] + g.posture_kp * ql + g.posture_kd * (r.qvel[fl] - v)
            idx = self.dofs[list(g.lead_joints)]
            a[idx] = lead[idx]
        H[self.dofs, self.dofs] += g.posture * sc["posture"]
        c[self.dofs] -= g.posture * sc["posture"] * a[self.dofs]
        H[np.arange(nv), np.arange(nv)] += g.reg_qdd
        # assemble
        P = np.zeros((self.n, self.n))
        P[:nv, :nv] = H
        P[np.arange(nv, nv + nl), np.arange(nv, nv + nl)] = g.reg_lam
        P[np.arange(nv + nl, self.n), np.arange(nv + nl, self.n)] = g.reg_tau + g.tau_rate
        q = np.concatenate([c, np.zeros(nl + nu)])
        if self.prev is not None and g.tau_rate > 0:
            q[nv + nl :] = -g.tau_rate * self.prev[nv + nl :]
        A[:nv, :nv] = M
        A[:nv, nv : nv + nl] = -cols
        A[self.dofs, nv + nl + np.arange(nu)] = -self.effort
        A[nv + np.arange(nl + nu), nv + np.arange(nl + nu)] = 1.0
        self.l[:nv] = self.u[:nv] = -h
        k = 0
        for i, pts in enumerate(self.points):
            self.u[nv + k : nv + k + 4 * len(pts)] = np.inf if stance[i] else 0.0
            k += 4 * len(pts)
        self.solver.update(Px=P[self._p_idx], Ax=A[self._a_idx], q=q, l=self.l, u=self.u)
        res = self.solver.solve(raise_error=False)
        status = str(res.info.status)
        x = res.x
        # an unconverged or infeasible iterate can be finite but huge: keep the previous solution then
        if (
            x is None
            or not np.all(np.isfinite(x))
            or np.abs(x[nv + nl :]).max() > 1.05 * g.torque_fraction
            or np.abs(x[:nv]).max() > MAX_QACC
        ):
            x = self.prev if self.prev is not None else np.zeros(self.n)
            status += " (previous kept)"
        self.prev = x
        lam = x[nv : nv + nl] * self.weight
        forces, k = {}, 0
        for name, pts in zip(self.contact_bodies, self.points):
            forces[name] = (self.U @ lam[k : k + 4 * len(pts)].reshape(-1, 4).T).T
            k += 4 * len(pts)
        return WbcSolution(x[:nv].copy(), x[nv + nl :] * self.effort, forces, status, int(res.info.iter))


def servo_targets(
    tau: np.ndarray,
    q: np.ndarray,
    v: np.ndarray,
    qdd: np.ndarray,
    kp: np.ndarray,
    kd: np.ndarray,
    period: float,
) -> np.ndarray:
    """PD targets that make ``kp (target - q) - kd v`` average ``tau`` over ``period`` [s] when the joints
    move with acceleration ``qdd`` (all joint-space arrays)."""
    qm = q + v * period / 2 + qdd * period**2 / 6
    vm = v + qdd * period / 2
    return qm + (tau + kd * vm) / kp
