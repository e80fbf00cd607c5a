"""Inverse dynamics of one clip frame on the shipped G1 with admissible contact wrenches.

For every frame the clip's ``qpos`` gives ``qvel`` and ``qacc`` by finite differences (central, 50 Hz),
and MuJoCo's ``mj_inverse`` (contacts and joint limits off) gives the generalised force
``h = M(q) qacc + c(q, qvel)`` the motion needs. The floor supplies ``G lam``: every contact vertex
pushes with a force inside a linearised friction cone (four generators ``n +- mu t``, ``lam >= 0``), so
each sole's wrench keeps its normal force non-negative and its centre of pressure inside the sole
polygon (``soles.sole_polygon``). The base rows must balance, ``h_base = (G lam)_base``; the joints
then need ``tau = h_joints - (G lam)_joints``.

Per frame, two solves:

1. ``lam*`` = argmin |S (h_base - A lam)|, ``lam >= 0`` (NNLS; ``S`` scales forces by ``FORCE_TOL``
   and moments by ``MOMENT_TOL``): the smallest base residual any admissible contact gives. A frame
   whose residual exceeds the tolerances cannot be produced by its contacts (a flight frame that is
   not ballistic, or a stance frame whose ZMP leaves the soles).
2. A dense active-set QP (qpOASES through CasADi; OSQP's ADMM stalled on these degenerate problems):
   minimise ``0.5 sum(r_i^2) + 0.5 W t^2`` over ``lam >= 0`` and ``t`` with ``r = tau / effort``,
   ``|r_i| <= t`` and ``A lam = h_base - residual*`` (the residual of step 1 is kept): the contact
   distribution that spares the joints, the worst one first.

Feet are in contact when the clip's stance flags say so (``stance_flags``: at a contact change, the
neighbouring frames' flags too), through the vertices of their sole polygon within ``FLOOR_HEIGHT`` of the
floor (all of a flat sole; the toe line of a foot on its toes); the pelvis, torso, knees and hands when their
lowest collision point is within ``FLOOR_HEIGHT`` of the floor (a fall or a crawl). Friction is the
model's: ``FOOT_FRICTION`` at the feet, none on the other capsules (``condim`` 1: normal force only).
A frame whose lowest collision point lies more than ``PENETRATION_TOL`` below the floor is not a contact
but a body through the floor (``InverseDynamics.lowest_point``): the check fails it.
"""

from __future__ import annotations

import contextlib
import copy
import io
from dataclasses import dataclass

import mujoco
import numpy as np

from .g1 import FOOT_FRICTION, g1_model
from .g1_constants import G1
from .soles import sole_polygon

__all__ = [
    "FLOOR_BODIES",
    "FLOOR_HEIGHT",
    "FORCE_TOL",
    "MOMENT_TOL",
    "PENETRATION_TOL",
    "FrameDynamics",
    "InverseDynamics",
    "finite_differences",
    "stance_flags",
]

MASS = 33.341
"""Total mass of the shipped G1 [kg] (``mj_getTotalmass``)."""
FORCE_TOL = 0.01 * MASS * 9.81
"""Largest base force residual of a feasible frame [N]: 1 % of the weight, a COM acceleration error of
0.1 m/s^2 (float32 clips 55 m from the origin give 2 ulp / dt^2 x m = 0.6 N of noise)."""
MOMENT_TOL = 0.01 * MASS * 9.81
"""Largest base moment residual of a feasible frame [N m]: the weight times 1 cm (the ZMP up to 1 cm
outside the support)."""
FLOOR_HEIGHT = 0.02
"""A non-foot body is on the floor when its lowest collision point is below this height, a stance sole's
vertex when it is [m]."""
PENETRATION_TOL = 0.01
"""Deepest a collision point of the clip's robot may lie below the floor [m]: one 50 Hz frame of a foot
landing at 0.5 m/s (a touchdown between two samples); deeper, the floor would have to give way (a swing
foot or shin through the floor), which no contact model of the check can account for."""
FLOOR_BODIES = (
    "pelvis",
    "torso_link",
    "left_knee_link",
    "right_knee_link",
    "left_wrist_yaw_link",
    "right_wrist_yaw_link",
)
"""Bodies other than the feet that may rest on the floor (fall, get-up, crawl)."""
REGULARISATION = 1e-8
"""Weight of |lam / LAM_SCALE|^2 in the torque QP (makes its Hessian positive definite)."""
LAM_SCALE = MASS * 9.81
"""Unit of the contact-force unknowns in the QP [N]."""
WORST_WEIGHT = 100.0
"""Weight W of the worst joint's squared ratio against the sum of all squared ratios [1]."""


def finite_differences(model: mujoco.MjModel, qpos: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """``qvel`` and ``qacc`` (T, nv) of a ``qpos`` trajectory: ``v_{t+1/2} = (q_{t+1} - q_t) / dt``
    (``mj_differentiatePos``), ``qvel_t`` their mean, ``qacc_t = (v_{t+1/2} - v_{t-1/2}) / dt``;
    the end frames copy their neighbour's acceleration (exact for quadratic motion)."""
    n = len(qpos)
    half = np.zeros((max(n - 1, 0), model.nv))
    for t in range(n - 1):
        mujoco.mj_differentiatePos(model, half[t], dt, qpos[t], qpos[t + 1])
    qvel, qacc = np.zeros((n, model.nv)), np.zeros((n, model.nv))
    if n < 2:
        return qvel, qacc
    qvel[0], qvel[-1] = half[0], half[-1]
    qvel[1:-1] = 0.5 * (half[:-1] + half[1:])
    if n >= 3:
        qacc[1:-1] = np.diff(half, axis=0) / dt
        qacc[0], qacc[-1] = qacc[1], qacc[-2]
    return qvel, qacc


def stance_flags(contacts: np.ndarray) -> np.ndarray:
    """Feet that may push in each frame: the clip's stance flags, and at a contact change those of the
    neighbouring frames too (a central difference at frame t averages the motion over t - 1 ... t + 1,
    so a frame next to a take-off or a landing carries part of the neighbouring phase's force)."""
    c = np.asarray(contacts, dtype=bool)
    out = c.copy()
    out[1:] |= c[:-1]
    out[:-1] |= c[1:]
    return out


@dataclass(frozen=True)
class FrameDynamics:
    """One frame's solution."""

    torque: np.ndarray
    """(29,) joint torques [N m], ``G1.joints`` order."""
    residual: np.ndarray
    """(6,) base wrench no admissible contact supplies: force [N] (world), moment [N m] (pelvis frame,
    about the pelvis origin). Zero when the frame is feasible."""
    wrenches: dict[str, np.ndarray]
    """Contact wrench per body in contact: (6,) force [N] and moment about the body origin [N m], world."""
    solver: str
    """``qpoases``, ``none`` (no contact), or ``nnls`` when the torque QP failed (step 1's forces kept)."""


@dataclass
class _Contact:
    body: str
    body_id: int
    points: np.ndarray  # (k, 3) world contact points
    mu: float


class InverseDynamics:
    """Per-frame solver on one compiled model (contacts and joint limits disabled for ``mj_inverse``)."""

    def __init__(self, model: mujoco.MjModel | None = None, *, mu: float = FOOT_FRICTION) -> None:
        self.model = copy.copy(model) if model is not None else g1_model(floor=False)
        self.model.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)
        self.data = mujoco.MjData(self.model)
        self.mu = mu
        self.effort = np.asarray(G1.effort)
        self.dofs = np.array([self.model.jnt_dofadr[self.model.joint(j).id] for j in G1.joints])
        self.soles = [sole_polygon(self.model, f) for f in G1.feet]
        self.feet = [self.model.body(f).id for f in G1.feet]
        self._collision_geoms = [
            g
            for g in range(self.model.ngeom)
            if self.model.geom_contype[g] + self.model.geom_conaffinity[g]
            and self.model.geom_bodyid[g] > 0
            and int(self.model.geom_type[g])
            in (int(mujoco.mjtGeom.mjGEOM_CAPSULE), int(mujoco.mjtGeom.mjGEOM_SPHERE))
        ]
        self.floor_bodies = []
        for name in FLOOR_BODIES:
            b = self.model.body(name).id
            geoms = [
                g
                for g in range(self.model.ngeom)
                if self.model.geom_bodyid[g] == b
                and self.model.geom_contype[g] + self.model.geom_conaffinity[g]
            ]
            friction = max(
                (self.model.geom_friction[g][0] for g in geoms if self.model.geom_condim[g] > 1), default=0.0
            )
            self.floor_bodies.append((name, b, geoms, float(friction)))

    def contacts(self, stance: np.ndarray) -> list[_Contact]:
        """Contacts of the posed ``data`` (after kinematics): stance feet and bodies on the floor."""
        m, d = self.model, self.data
        out = []
        for i, foot in enumerate(self.feet):
            if stance[i]:
                pts = d.xpos[foot] + self.soles[i] @ d.xmat[foot].reshape(3, 3).T
                pts = pts[pts[:, 2] < FLOOR_HEIGHT]  # a pitched sole (heel or toe up) pushes on what touches
                if len(pts):
                    out.append(_Contact(G1.feet[i], foot, pts, self.mu))
        for name, b, geoms, friction in self.floor_bodies:
            best, point = np.inf, None
            for g in geoms:
                half = m.geom_size[g][1] if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_CAPSULE else 0.0
                axis = d.geom_xmat[g].reshape(3, 3)[:, 2]
                ends = np.array([d.geom_xpos[g] - half * axis, d.geom_xpos[g] + half * axis])
                k = int(np.argmin(ends[:, 2]))
                low = ends[k, 2] - m.geom_size[g][0]
                if low < best:
                    best, point = low, ends[k] - np.array([0.0, 0.0, m.geom_size[g][0]])
            if best < FLOOR_HEIGHT:
                out.append(_Contact(name, b, point[None, :], friction))
        return out

    def lowest_point(self) -> tuple[float, str]:
        """Height [m] of the posed ``data``'s lowest collision point (capsules and spheres), and its body."""
        m, d = self.model, self.data
        best, body = np.inf, ""
        for g in self._collision_geoms:
            half = m.geom_size[g][1] if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_CAPSULE else 0.0
            low = d.geom_xpos[g][2] - half * abs(d.geom_xmat[g][8]) - m.geom_size[g][0]
            if low < best:
                best, body = float(low), m.body(m.geom_bodyid[g]).name
        return best, body

    def solve(
        self, qpos: np.ndarray, qvel: np.ndarray, qacc: np.ndarray, stance: np.ndarray
    ) -> FrameDynamics:
        """Joint torques and contact wrenches of one frame (``stance``: left and right foot flags)."""
        m, d = self.model, self.data
        d.qpos[:], d.qvel[:] = qpos, qvel
        mujoco.mj_forward(m, d)
        d.qacc[:] = qacc
        mujoco.mj_inverse(m, d)
        h = d.qfrc_inverse.copy()
        contacts = self.contacts(stance)
        cols, owner, points = [], [], []
        jacp = np.zeros((3, m.nv))
        for ci, c in enumerate(contacts):
            gens = _generators(c.mu)
            for p in c.points:
                mujoco.mj_jac(m, d, jacp, None, p, c.body_id)
                for u in gens:
                    cols.append(jacp.T @ u)
                    owner.append(ci)
                    points.append((p, u))
        h_base, h_joint = h[:6], h[self.dofs]
        if not cols:
            return FrameDynamics(h_joint, h_base, {}, "none")
        g = np.array(cols).T
        a, b = g[:6], g[self.dofs]
        lam, residual = _min_residual(a, h_base)
        lam, solver = _min_torque(a, b, h_base - residual, h_joint, self.effort, lam)
        residual = h_base - a @ lam
        wrenches: dict[str, np.ndarray] = {c.body: np.zeros(6) for c in contacts}
        for k, (p, u) in enumerate(points):
            c = contacts[owner[k]]
            f = lam[k] * u
            wrenches[c.body][:3] += f
            wrenches[c.body][3:] += np.cross(p - d.xpos[c.body_id], f)
        return FrameDynamics(h_joint - b @ lam, residual, wrenches, solver)


def _generators(mu: float) -> np.ndarray:
    """Edges of the linearised friction cone (world frame, floor normal z): ``n +- mu t_x``, ``n +- mu
    t_y`` (the pyramid |f_x| + |f_y| <= mu f_z inscribed in the cone); ``mu = 0``: the normal only."""
    if mu <= 0:
        return np.array([[0.0, 0.0, 1.0]])
    return np.array([[mu, 0, 1], [-mu, 0, 1], [0, mu, 1], [0, -mu, 1]], dtype=float)


_SCALE = np.array([1 / FORCE_TOL] * 3 + [1 / MOMENT_TOL] * 3)


def _min_residual(a: np.ndarray, h_base: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    from scipy.optimize import nnls

    lam, _ = nnls(_SCALE[:, None] * a, _SCALE * h_base, maxiter=50 * a.shape[1])
    return lam, h_base - a @ lam


def _qp(n: int, m: int):
    """A fresh dense qpOASES solver (CasADi ``conic``; a reused one would hot-start from the previous
    frame's working set, making a frame's answer depend on the frames checked before it)."""
    import casadi as ca

    with contextlib.redirect_stdout(io.StringIO()):  # qpOASES prints its licence notice
        return ca.conic(
            "torque",
            "qpoases",
            {"h": ca.Sparsity.dense(n, n), "a": ca.Sparsity.dense(m, n)},
            {"printLevel": "none", "error_on_fail": False},
        )


def _min_torque(
    a: np.ndarray,
    b: np.ndarray,
    target: np.ndarray,
    h_joint: np.ndarray,
    effort: np.ndarray,
    lam0: np.ndarray,
) -> tuple[np.ndarray, str]:
    n, j = a.shape[1], len(h_joint)
    a = a * LAM_SCALE  # unknowns x = lam / LAM_SCALE: O(1) for the weight shared by a few vertices
    bn, hn = b * LAM_SCALE / effort[:, None], h_joint / effort  # ratio r = hn - bn x
    p = np.zeros((n + 1, n + 1))
    p[:n, :n] = bn.T @ bn + REGULARISATION * np.eye(n)
    p[n, n] = WORST_WEIGHT
    q = np.concatenate([-bn.T @ hn, [0.0]])
    one = np.ones((j, 1))
    rows = np.vstack(
        [
            np.hstack([a, np.zeros((6, 1))]),  # base equations
            np.hstack([bn, one]),  # hn - bn x <= t
            np.hstack([-bn, one]),  # -(hn - bn x) <= t
        ]
    )
    x0 = lam0 / LAM_SCALE
    # A frame step 1 could not balance has its target on the boundary of the reachable base wrenches;
    # should the active-set solver fail on that degenerate face, it retries with a band of 1e-3 of the
    # tolerances around it.
    for band in (0.0, 1e-3 / _SCALE):
        solver = _qp(n + 1, len(rows))
        res = solver(
            h=p,
            g=q,
            a=rows,
            lba=np.concatenate([target - band, hn, -hn]),
            uba=np.concatenate([target + band, np.full(2 * j, np.inf)]),
            lbx=np.zeros(n + 1),
            ubx=np.full(n + 1, np.inf),
            x0=np.concatenate([x0, [np.abs(hn - bn @ x0).max()]]),
        )
        x = np.asarray(res["x"]).ravel()
        if solver.stats()["success"] and np.all(np.isfinite(x)):
            return np.maximum(x[:n], 0.0) * LAM_SCALE, "qpoases"
    return lam0, "nnls"
