"""Inverse kinematics of a serial arm with Pinocchio and an OSQP quadratic-programming step.

``chain_from_mujoco`` builds a Pinocchio model of the revolute chain that ends at a MuJoCo site,
taking joint placements and axes from a compiled ``MjModel`` (so the arm is exactly the one the
simulator integrates, wherever it is mounted). ``solve_ik`` iterates a QP per step:

    min_dq  |W (J dq - e)|^2 + damping |dq|^2 + posture |q + dq - q_ref|^2
    s.t.    max(q_min - q, -max_step) <= dq <= min(q_max - q, max_step)

where e stacks the position error [m] and, optionally, the tool-axis error (cross product of the
current and desired axis, linearised as -[a]x J_w dq). Joint limits are constraints, so every iterate
is inside the limits. A target that cannot be reached ends with ``converged = False`` and its
residual, never an exception.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np
import osqp
import pinocchio as pin
from scipy import sparse

from rle_design.scene.elements import element_id, element_ids

__all__ = ["ArmChain", "IkResult", "chain_from_mujoco", "solve_ik"]


@dataclass(frozen=True)
class ArmChain:
    """Pinocchio model of a revolute chain taken from a MuJoCo model.

    Attributes:
        model: Pinocchio model; configuration order = ``joint_names``.
        tool_frame: Pinocchio frame id of the tool site.
        joint_names: MuJoCo joint names, base to tip.
        qpos_adr: MuJoCo ``qpos`` addresses of the joints.
        dof_adr: MuJoCo ``qvel`` addresses of the joints.
        base_body: MuJoCo body id whose frame is the chain's base frame.
        lower: Lower joint limits [rad].
        upper: Upper joint limits [rad].
    """

    model: pin.Model
    tool_frame: int
    joint_names: tuple[str, ...]
    qpos_adr: np.ndarray
    dof_adr: np.ndarray
    base_body: int
    lower: np.ndarray
    upper: np.ndarray

    def base_pose(self, data: mujoco.MjData) -> tuple[np.ndarray, np.ndarray]:
        """World position [m] and rotation matrix of the chain base in ``data``."""
        return data.xpos[self.base_body].copy(), data.xmat[self.base_body].reshape(3, 3).copy()

    def to_base(self, data: mujoco.MjData, point_world: np.ndarray) -> np.ndarray:
        """Express a world point [m] in the chain base frame."""
        p, r = self.base_pose(data)
        return r.T @ (np.asarray(point_world, dtype=float) - p)

    def tool(self, q: np.ndarray) -> pin.SE3:
        """Tool pose in the base frame at configuration ``q``."""
        d = self.model.createData()
        pin.framesForwardKinematics(self.model, d, np.asarray(q, dtype=float))
        return d.oMf[self.tool_frame].copy()


@dataclass(frozen=True)
class IkResult:
    """Outcome of ``solve_ik``.

    Attributes:
        q: Joint configuration [rad] (within limits).
        position_error: Distance of the tool to the target [m].
        axis_error: Angle between tool axis and desired axis [rad] (0 without an axis task).
        iterations: QP steps taken.
        converged: Both errors are below their tolerances.
    """

    q: np.ndarray
    position_error: float
    axis_error: float
    iterations: int
    converged: bool


def _xform(pos: np.ndarray, mat: np.ndarray) -> pin.SE3:
    return pin.SE3(np.asarray(mat, dtype=float).reshape(3, 3), np.asarray(pos, dtype=float))


def chain_from_mujoco(model: mujoco.MjModel, joint_names: Sequence[str], site_name: str) -> ArmChain:
    """Pinocchio chain of hinge joints ``joint_names`` (base to tip) ending at site ``site_name``.

    Placements are read at the zero configuration of these joints, so intermediate bodies without
    joints (fixed links) are folded into the placements.

    Raises:
        MissingElement: A joint or the site does not exist.
    """
    jids = element_ids(model, "joint", joint_names, code="ik.missing_joint")
    sid = element_id(model, "site", site_name, code="ik.missing_site")
    data = mujoco.MjData(model)
    data.qpos[:] = model.qpos0
    for j in jids:
        data.qpos[model.jnt_qposadr[j]] = 0.0
    mujoco.mj_kinematics(model, data)
    base_body = int(model.body_parentid[model.jnt_bodyid[jids[0]]])
    world_base = _xform(data.xpos[base_body], data.xmat[base_body])
    pm = pin.Model()
    parent, prev = 0, world_base
    lower, upper = [], []
    for name, j in zip(joint_names, jids):
        b = model.jnt_bodyid[j]
        frame = _xform(data.xpos[b], data.xmat[b]) * pin.SE3(np.eye(3), model.jnt_pos[j].copy())
        axis = model.jnt_axis[j].copy()
        parent = pm.addJoint(parent, pin.JointModelRevoluteUnaligned(axis), prev.inverse() * frame, name)
        prev = frame
        lo, hi = model.jnt_range[j] if model.jnt_limited[j] else (-np.pi, np.pi)
        lower.append(lo)
        upper.append(hi)
    pm.lowerPositionLimit = np.array(lower)
    pm.upperPositionLimit = np.array(upper)
    tool = prev.inverse() * _xform(data.site_xpos[sid], data.site_xmat[sid])
    fid = pm.addFrame(pin.Frame("tool", parent, tool, pin.FrameType.OP_FRAME))
    return ArmChain(
        pm,
        fid,
        tuple(joint_names),
        np.array([model.jnt_qposadr[j] for j in jids]),
        np.array([model.jnt_dofadr[j] for j in jids]),
        base_body,
        np.array(lower),
        np.array(upper),
    )


class _BoxQP:
    """min 1/2 x'Hx + g'x s.t. lo <= x <= hi with one OSQP workspace whose sparsity never changes
    (dense upper triangle of H, identity constraints): later steps only update the numbers."""

    def __init__(self, n: int) -> None:
        self.n = n
        self.rows, self.cols = np.triu_indices(n)
        order = np.lexsort((self.rows, self.cols))  # CSC order: by column, then row
        self.rows, self.cols = self.rows[order], self.cols[order]
        self.pattern = sparse.csc_matrix((np.ones(len(self.rows)), (self.rows, self.cols)), shape=(n, n))
        self.prob: osqp.OSQP | None = None

    def solve(self, h: np.ndarray, g: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        # H is positive definite (damping > 0): when the unconstrained minimiser is inside the box it
        # is the QP's solution, and OSQP is only needed when a limit is active.
        x = np.linalg.solve(h, -g)
        if np.all(x >= lo) and np.all(x <= hi):
            return x
        px = h[self.rows, self.cols]
        if self.prob is None:
            self.prob = osqp.OSQP()
            p = self.pattern.copy()
            p.data = px.copy()
            self.prob.setup(
                P=p,
                q=g,
                A=sparse.identity(self.n, format="csc"),
                l=lo,
                u=hi,
                verbose=False,
                eps_abs=1e-9,
                eps_rel=1e-9,
                polishing=False,
            )
        else:
            self.prob.update(Px=px, q=g, l=lo, u=hi)
        x = self.prob.solve(raise_error=False).x
        if x is None or not np.all(np.isfinite(x)):
            return np.zeros(self.n)
        return np.clip(x, lo, hi)


def solve_ik(
    chain: ArmChain,
    target: np.ndarray,
    q0: np.ndarray,
    *,
    axis: np.ndarray | None = None,
    tool_axis: tuple[float, float, float] = (0.0, 0.0, 1.0),
    axis_weight: float = 0.3,
    q_ref: np.ndarray | None = None,
    posture: float = 1e-5,
    damping: float = 1e-4,
    max_step: float = 0.2,
    tol: float = 1e-3,
    axis_tol: float = np.radians(2.0),
    max_iter: int = 150,
) -> IkResult:
    """Joint configuration placing the tool at ``target`` (chain base frame) [m].

    Args:
        chain: Arm chain.
        target: Target tool position in the base frame [m].
        q0: Initial configuration [rad] (clipped into the limits).
        axis: Desired direction of the tool's ``tool_axis`` in the base frame, or None.
        tool_axis: Axis of the tool frame that must point along ``axis``.
        axis_weight: Weight of the axis error relative to position [m/rad].
        q_ref: Posture the null space is pulled toward (default ``q0``).
        posture: Weight of the posture term [1].
        damping: Levenberg-Marquardt damping of the step [1].
        max_step: Largest change of any joint per iteration [rad].
        tol: Position tolerance [m].
        axis_tol: Axis tolerance [rad].
        max_iter: Iteration limit.
    """
    m, d = chain.model, chain.model.createData()
    lo_q, hi_q = chain.lower, chain.upper
    q = np.clip(np.asarray(q0, dtype=float), lo_q, hi_q)
    q_ref = q.copy() if q_ref is None else np.asarray(q_ref, dtype=float)
    target = np.asarray(target, dtype=float)
    want = None if axis is None else np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    pos_err = axis_err = float("inf")
    qp = _BoxQP(len(q))
    it = 0
    for it in range(1, max_iter + 1):
        pin.framesForwardKinematics(m, d, q)
        pin.computeJointJacobians(m, d, q)
        tf = d.oMf[chain.tool_frame]
        jac = pin.getFrameJacobian(m, d, chain.tool_frame, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
        e_p = target - tf.translation
        pos_err = float(np.linalg.norm(e_p))
        rows, errs = [jac[:3]], [e_p]
        axis_err = 0.0
        if want is not None:
            a = tf.rotation @ np.asarray(tool_axis)
            axis_err = float(np.arccos(np.clip(np.dot(a, want), -1.0, 1.0)))
            skew = pin.skew(a)
            rows.append(axis_weight * (-skew @ jac[3:]))
            errs.append(axis_weight * (want - a))
        if pos_err < tol and axis_err < axis_tol:
            return IkResult(q, pos_err, axis_err, it - 1, True)
        jm, e = np.vstack(rows), np.concatenate(errs)
        n = len(q)
        h = jm.T @ jm + (damping + posture) * np.eye(n)
        g = -(jm.T @ e) - posture * (q_ref - q)
        step_lo = np.maximum(lo_q - q, -max_step)
        step_hi = np.minimum(hi_q - q, max_step)
        dq = qp.solve(h, g, step_lo, step_hi)
        if np.linalg.norm(dq) < 1e-7:
            break
        q = np.clip(q + dq, lo_q, hi_q)
    pin.framesForwardKinematics(m, d, q)
    tf = d.oMf[chain.tool_frame]
    pos_err = float(np.linalg.norm(target - tf.translation))
    if want is not None:
        axis_err = float(np.arccos(np.clip(np.dot(tf.rotation @ np.asarray(tool_axis), want), -1.0, 1.0)))
    return IkResult(q, pos_err, axis_err, it, pos_err < tol and axis_err < axis_tol)
