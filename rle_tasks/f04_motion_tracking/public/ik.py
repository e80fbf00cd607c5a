"""Foot-placement inverse kinematics of the G1 legs (MuJoCo Jacobians, damped least squares).

Given the pelvis pose and every non-leg joint, each leg's six joints are solved so that its foot body
(``*_ankle_roll_link``) reaches a target position and yaw with the sole flat. Stance targets are held
to 0.05 mm; swing targets weight the orientation lower (``SWING_ORI_WEIGHT``). Joints are clamped
to their ranges after every iteration.
"""

from __future__ import annotations

import mujoco
import numpy as np

from .g1_constants import G1

__all__ = ["LegIK", "foot_quat", "yaw_quat"]

SWING_ORI_WEIGHT = 0.3
"""Weight of the foot orientation error in swing (stance: 1) [1]."""
DAMPING = 1e-2
"""Damped-least-squares damping lambda [m]."""
SWING_ITERS = 8
"""Iterations spent on a swing foot: it follows its target from the last frame's solution and, when the
target is out of reach, stops short instead of crossing the straight-knee singularity."""
MAX_STEP = 0.1
"""Largest joint change of one iteration [rad] (keeps the solver off the straight-knee singularity)."""


def yaw_quat(yaw: float) -> np.ndarray:
    """Quaternion (w x y z) of a rotation ``yaw`` [rad] about z."""
    return np.array([np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)])


def foot_quat(yaw: float, pitch: float = 0.0) -> np.ndarray:
    """Quaternion (w x y z) of a foot yawed by ``yaw`` and pitched by ``pitch`` [rad] about its own y axis
    (positive: toes down, heel up)."""
    if pitch == 0.0:
        return yaw_quat(yaw)
    out = np.zeros(4)
    mujoco.mju_mulQuat(out, yaw_quat(yaw), np.array([np.cos(pitch / 2), 0.0, np.sin(pitch / 2), 0.0]))
    return out


class LegIK:
    """Solver bound to one compiled model (free-base G1)."""

    def __init__(self, model: mujoco.MjModel) -> None:
        self.model = model
        self.data = mujoco.MjData(model)
        self.feet = [model.body(f).id for f in G1.feet]
        self.dofs = [np.arange(6 + 6 * leg, 12 + 6 * leg) for leg in (0, 1)]  # qvel indices
        jids = [model.joint(j).id for j in G1.joints]
        self.lo = model.jnt_range[jids, 0] + 1e-3
        self.hi = model.jnt_range[jids, 1] - 1e-3

    def solve(
        self,
        qpos: np.ndarray,
        targets: list[tuple[np.ndarray, float, bool] | None],
        iters: int = 200,
        tol: float = 5e-5,
        swing_iters: int = SWING_ITERS,
        swing_knee_min: float | None = None,
    ) -> tuple[np.ndarray, float]:
        """Leg joints of ``qpos`` (36) solved for ``targets`` (one per foot, left first; None: leg left as is;
        ``(pos, yaw, stance[, pitch])``, pitch about the foot's y axis). A swing target gets ``swing_iters``
        iterations and its knee is kept at ``swing_knee_min`` or more (None: its range).

        Returns:
            The solved ``qpos`` and the largest remaining position error [m] of a stance foot.
        """
        m, d = self.model, self.data
        d.qpos[:] = qpos
        jacp, jacr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
        res = np.zeros(3)
        worst = 0.0
        for it in range(iters):
            mujoco.mj_kinematics(m, d)
            mujoco.mj_comPos(m, d)
            done = True
            worst = 0.0
            for leg, target in enumerate(targets):
                if target is None:
                    continue
                pos, yaw, stance, *pitch = target
                b = self.feet[leg]
                ep = np.asarray(pos) - d.xpos[b]
                mujoco.mju_subQuat(res, foot_quat(yaw, pitch[0] if pitch else 0.0), d.xquat[b])
                eo = d.xmat[b].reshape(3, 3) @ res
                w = 1.0 if stance else SWING_ORI_WEIGHT
                if stance:
                    worst = max(worst, float(np.linalg.norm(ep)))
                if np.linalg.norm(ep) < tol and w * np.linalg.norm(eo) < tol * 10:
                    continue
                if not stance and it >= swing_iters:
                    continue
                done = False
                mujoco.mj_jacBody(m, d, jacp, jacr, b)
                cols = self.dofs[leg]
                jac = np.vstack([jacp[:, cols], w * jacr[:, cols]])
                err = np.concatenate([ep, w * eo])
                dq = jac.T @ np.linalg.solve(jac @ jac.T + DAMPING**2 * np.eye(6), err)
                dq *= min(1.0, MAX_STEP / max(float(np.abs(dq).max()), 1e-12))
                q = d.qpos[7 + cols - 6] + dq
                lo = self.lo[cols - 6].copy()
                if not stance and swing_knee_min is not None:
                    lo[3] = max(lo[3], swing_knee_min)
                d.qpos[7 + cols - 6] = np.clip(q, lo, self.hi[cols - 6])
            if done:
                break
        return d.qpos.copy(), worst
