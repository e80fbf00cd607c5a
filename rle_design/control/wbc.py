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

The task weights and gains are in ``wbc_tasks``, the reference motion's kinematics in ``wbc_reference``.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
import scipy.sparse as sp

from rle_design.control.wbc_reference import MotionReference, _body_jac
from rle_design.control.wbc_tasks import WbcGains

__all__ = [
    "WbcSolution",
    "WholeBodyQP",
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
