"""Gravity-balancing co-design: springs and counterweights chosen by an optimiser (CasADi + IPOPT).

Given a serial arm (a Pinocchio ``KinematicModel``) and a grid of poses, choose zero-length spring
anchor points and stiffnesses and counterweight positions and masses, each within its slot's bounds,
to minimise the worst-case holding residual over the grid::

    r(q) = g(q) + sum_cw J_c(q)^T m_c g_up + sum_arm J_a(q)^T m_a g_up
                + sum_springs k (J_b(q) - J_a(q))^T (x_b(q) - x_a(q))

    minimise  t + w_mass * (added mass)   s.t.  -t <= r_i(q_j) <= t  for every joint i and pose j

where ``g(q)`` is Pinocchio's generalized gravity of the bare arm, ``g_up = -gravity``, a
counterweight is a point mass ``m_c`` at ``p`` in its joint's frame, carried by a printed arm of
linear density ``lambda`` from ``attach`` to ``p`` (mass ``lambda |p - attach|`` at the midpoint,
counted in the residual and in the added mass), and a zero-length spring of stiffness ``k`` pulls
``x_b`` towards ``x_a`` with generalized force ``-k (J_b - J_a)^T (x_b - x_a)``.

Pose-dependent quantities (joint placements and Jacobians) are evaluated numerically by Pinocchio at
each grid pose; the decision variables enter symbolically, so IPOPT sees exact derivatives. Closed
forms pinned in ``tests/kinematics/test_codesign.py``: ``k a b = m g l`` for one link and a
zero-length spring, ``m_c r_c = sum m_i l_i`` for a counterweight.

CasADi is the ``opt`` extra and is imported on first use.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin

from rle_design.errors import RleError
from rle_design.kinematics.model import KinematicModel

__all__ = ["CodesignError", "CodesignResult", "CounterweightSlot", "SpringSlot", "optimise_balance"]

Vec3 = tuple[float, float, float]


class CodesignError(RleError):
    """A slot that cannot be optimised (unknown joint, empty bounds) or a solver failure."""

    code = "kinematics.codesign"


@dataclass(frozen=True)
class CounterweightSlot:
    """Where a counterweight may go.

    Attributes:
        name: Label used in the result.
        joint: Pinocchio joint id of the link that carries it.
        lower: Lower corner of the allowed box for its centre, in the joint frame [m].
        upper: Upper corner [m] (equal to ``lower`` fixes the position).
        max_mass: Largest counterweight mass [kg].
        attach: Where its printed arm leaves the link, in the joint frame [m].
        arm_density: Mass per metre of the printed arm [kg/m]; 0 for a weight fixed on the link.
    """

    name: str
    joint: int
    lower: Vec3
    upper: Vec3
    max_mass: float
    attach: Vec3 = (0.0, 0.0, 0.0)
    arm_density: float = 0.0


@dataclass(frozen=True)
class SpringSlot:
    """Where a zero-length spring may go.

    Attributes:
        name: Label used in the result.
        anchor_joint: Pinocchio joint id of the body of the fixed end (0 = the world).
        anchor_lower: Lower corner of the anchor box, in that joint frame [m].
        anchor_upper: Upper corner [m].
        attach_joint: Pinocchio joint id of the moving end's body.
        attach_lower: Lower corner of the attachment box, in that joint frame [m].
        attach_upper: Upper corner [m].
        max_stiffness: Largest stiffness [N/m].
        min_stiffness: Smallest stiffness [N/m]; equal to ``max_stiffness`` for a catalog spring of
            fixed rate (``rle_design.catalog`` ``springs``), whose balance then comes from its ends.
    """

    name: str
    anchor_joint: int
    anchor_lower: Vec3
    anchor_upper: Vec3
    attach_joint: int
    attach_lower: Vec3
    attach_upper: Vec3
    max_stiffness: float
    min_stiffness: float = 0.0


@dataclass(frozen=True)
class CodesignResult:
    """Optimised passive elements and the residual they leave.

    Attributes:
        counterweights: ``name -> (position in the joint frame [m], mass [kg], printed-arm mass [kg])``.
        springs: ``name -> (anchor [m], attachment [m], stiffness [N/m])``.
        added_mass: Counterweights plus printed arms [kg].
        worst_residual: ``max |r|`` over the grid and the optimised joints [N m].
        residual: ``r(q)`` per grid pose, shape (N, nv) [N m].
        status: IPOPT's return status.
    """

    counterweights: dict[str, tuple[np.ndarray, float, float]]
    springs: dict[str, tuple[np.ndarray, np.ndarray, float]]
    added_mass: float
    worst_residual: float
    residual: np.ndarray
    status: str


def _check_box(name: str, lo: Vec3, hi: Vec3) -> None:
    if len(lo) != 3 or len(hi) != 3 or any(a > b for a, b in zip(lo, hi, strict=True)):
        raise CodesignError(f"slot '{name}': lower {lo} must not exceed upper {hi} (3 values each, m)")


def _placements(km: KinematicModel, grid: np.ndarray, joints: set[int]) -> list[dict[int, tuple]]:
    """Per pose: joint id -> (rotation, translation, 6 x nv LOCAL_WORLD_ALIGNED Jacobian)."""
    out = []
    for q in grid:
        pin.computeJointJacobians(km.model, km.data, q)
        per: dict[int, tuple] = {}
        for j in joints:
            if j == 0:
                per[0] = (np.eye(3), np.zeros(3), np.zeros((6, km.model.nv)))
                continue
            oMi = km.data.oMi[j]
            jac = pin.getJointJacobian(km.model, km.data, j, pin.LOCAL_WORLD_ALIGNED)
            per[j] = (oMi.rotation.copy(), oMi.translation.copy(), np.array(jac))
        out.append(per)
    return out


def _point(ca: Any, frame: tuple, local: Any) -> tuple[Any, Any]:
    """World position and 3 x nv linear Jacobian of a point given in a joint frame."""
    rot, trans, jac = frame
    w = ca.mtimes(ca.DM(rot), local)
    skew = ca.vertcat(
        ca.horzcat(0, -w[2], w[1]),
        ca.horzcat(w[2], 0, -w[0]),
        ca.horzcat(-w[1], w[0], 0),
    )
    jlin = ca.DM(jac[:3]) - ca.mtimes(skew, ca.DM(jac[3:]))
    return ca.DM(trans) + w, jlin


def optimise_balance(
    km: KinematicModel,
    grid: np.ndarray,
    *,
    counterweights: tuple[CounterweightSlot, ...] = (),
    springs: tuple[SpringSlot, ...] = (),
    mass_budget: float = np.inf,
    mass_weight: float = 0.0,
    joints: tuple[int, ...] | None = None,
    tol: float = 1e-10,
) -> CodesignResult:
    """Choose counterweights and springs that minimise the worst-case holding residual on ``grid``.

    Args:
        km: Arm model (``model_from_mujoco``/``model_from_mjcf``).
        grid: Poses, shape (N, nq) [rad].
        counterweights: Counterweight slots.
        springs: Zero-length spring slots.
        mass_budget: Largest added mass (counterweights and printed arms) [kg].
        mass_weight: Objective weight of the added mass [N m/kg] (0: residual only).
        joints: Velocity indices whose residual counts (default: all).
        tol: IPOPT tolerance.

    Returns:
        The optimised elements and the residual on the grid.

    Raises:
        CodesignError: A slot names a joint the model lacks or has an empty box; IPOPT failed.
    """
    try:
        import casadi as ca
    except ImportError as exc:  # pragma: no cover - the opt extra is part of the lock
        raise CodesignError("the co-design optimiser needs CasADi: pip install 'rle-bench[opt]'") from exc
    grid = np.atleast_2d(np.asarray(grid, float))
    nv = km.model.nv
    if grid.shape[1] != km.model.nq:
        raise CodesignError(f"grid has {grid.shape[1]} coordinates per pose, the model {km.model.nq}")
    rows = list(range(nv)) if joints is None else list(joints)
    used: set[int] = set()
    for c in counterweights:
        _check_box(c.name, c.lower, c.upper)
        used.add(c.joint)
    for s in springs:
        _check_box(s.name, s.anchor_lower, s.anchor_upper)
        _check_box(s.name, s.attach_lower, s.attach_upper)
        used |= {s.anchor_joint, s.attach_joint}
    bad = sorted(j for j in used if not 0 <= j < km.model.njoints)
    if bad:
        raise CodesignError(f"joint ids {bad} not in the model (0..{km.model.njoints - 1})")
    frames = _placements(km, grid, used)
    g_up = -np.asarray(km.model.gravity.linear, float)
    opti = ca.Opti()
    t = opti.variable()
    added = 0
    cw_vars = []
    for c in counterweights:
        m = opti.variable()
        p = opti.variable(3)
        opti.subject_to(opti.bounded(0.0, m, c.max_mass))
        opti.subject_to(opti.bounded(ca.DM(c.lower), p, ca.DM(c.upper)))
        opti.set_initial(m, 0.5 * c.max_mass)
        opti.set_initial(p, 0.5 * (np.asarray(c.lower) + np.asarray(c.upper)))
        d = p - ca.DM(c.attach)
        arm = c.arm_density * ca.sqrt(ca.sumsqr(d) + 1e-12)
        added = added + m + arm
        cw_vars.append((c, m, p, arm))
    sp_vars = []
    for s in springs:
        k = opti.variable()
        a = opti.variable(3)
        b = opti.variable(3)
        if not 0.0 <= s.min_stiffness <= s.max_stiffness:
            raise CodesignError(
                f"slot '{s.name}': stiffness bounds {s.min_stiffness} .. {s.max_stiffness} N/m are not ordered"
            )
        opti.subject_to(opti.bounded(s.min_stiffness, k, s.max_stiffness))
        opti.subject_to(opti.bounded(ca.DM(s.anchor_lower), a, ca.DM(s.anchor_upper)))
        opti.subject_to(opti.bounded(ca.DM(s.attach_lower), b, ca.DM(s.attach_upper)))
        opti.set_initial(k, 0.5 * (s.min_stiffness + s.max_stiffness))
        opti.set_initial(a, 0.5 * (np.asarray(s.anchor_lower) + np.asarray(s.anchor_upper)))
        opti.set_initial(b, 0.5 * (np.asarray(s.attach_lower) + np.asarray(s.attach_upper)))
        sp_vars.append((s, k, a, b))
    if counterweights and np.isfinite(mass_budget):
        opti.subject_to(added <= mass_budget)
    residuals = []
    for q, per in zip(grid, frames, strict=True):
        r = ca.DM(np.asarray(pin.computeGeneralizedGravity(km.model, km.data, q)))
        for c, m, p, arm in cw_vars:
            _, jc = _point(ca, per[c.joint], p)
            _, ja = _point(ca, per[c.joint], 0.5 * (p + ca.DM(c.attach)))
            r = r + ca.mtimes(jc.T, ca.DM(g_up)) * m + ca.mtimes(ja.T, ca.DM(g_up)) * arm
        for s, k, a, b in sp_vars:
            xa, ja = _point(ca, per[s.anchor_joint], a)
            xb, jb = _point(ca, per[s.attach_joint], b)
            r = r + k * ca.mtimes((jb - ja).T, xb - xa)
        residuals.append(r)
        for i in rows:
            opti.subject_to(opti.bounded(-t, r[i], t))
    opti.minimize(t + mass_weight * added)
    opti.solver("ipopt", {"print_time": False}, {"print_level": 0, "sb": "yes", "tol": tol, "max_iter": 3000})
    try:
        sol = opti.solve()
    except RuntimeError as exc:
        raise CodesignError(f"IPOPT did not converge: {opti.return_status()}") from exc
    res = np.array([np.asarray(sol.value(r)).reshape(-1) for r in residuals]).reshape(len(grid), nv)
    return CodesignResult(
        counterweights={
            c.name: (np.asarray(sol.value(p), float).reshape(3), float(sol.value(m)), float(sol.value(arm)))
            for c, m, p, arm in cw_vars
        },
        springs={
            s.name: (
                np.asarray(sol.value(a), float).reshape(3),
                np.asarray(sol.value(b), float).reshape(3),
                float(sol.value(k)),
            )
            for s, k, a, b in sp_vars
        },
        added_mass=float(sol.value(added)) if cw_vars else 0.0,
        worst_residual=float(np.max(np.abs(res[:, rows]))) if len(rows) else 0.0,
        residual=res,
        status=str(opti.return_status()),
    )
