"""Refinement of running clips (run, sprint) by the feasibility check's own inverse dynamics.

A keyed running clip (ballistic pelvis in flight, half-sine stance force) is not dynamically consistent:
the swinging limbs move the whole-body COM and angular momentum in flight, and the stance centre of
pressure (CoP) leaves the sole. ``refine`` iterates: the clip's base wrench ``h_base`` (``mj_inverse`` of
the finite-differenced ``qpos``, as ``inverse_dynamics`` computes it) gives, per frame, what the contacts
would have to supply; one sparse least-squares problem per axis then finds the smallest change of the
pelvis translation and rotation that

- makes every flight frame's base wrench zero (COM acceleration -g, constant angular momentum: the base
  rotation absorbs the rate of the limbs' angular momentum, I d2(theta) = -L'),
- keeps the stance CoP in a band on the sole (ahead of the ankle: ``BAND_X``, ``BAND_Y``; written as moments
  CoP x F_z, so that frames with little normal force stay well posed), before a lift-off on the sole that
  stays, in other double-stance frames near the support reference (``DOUBLE_BAND``),
- keeps the normal force above ``F_MIN``, |f_x| + |f_y| within ``FRICTION`` F_z (the check's pyramid) and
  the yaw moment about the foot that stays within ``YAW_ARM`` F_z,
- keeps the single-stance hip pitch torque within ``HIP_CAP`` (``_stance_hip``),

linearised with the COM moving with the pelvis and the composite rigid-body inertia, with weights on the
corrections and on the pitch and roll corrections' angular acceleration (``W_SMOOTH_ROT``); the clip is
keyed again with the corrected pelvis (the stance legs re-solved by IK) and the loop repeats. The shipped
run (``styles.refined_plan("run")``) met the check's torque and residual criteria with these settings (their
neighbours miss by a few frames; README, Clips step 8) but its joint-space swings go through the floor, which
the check now fails; the sprint's gait is not feasible either.
"""

from __future__ import annotations

from dataclasses import replace

import mujoco
import numpy as np
from scipy import sparse
from scipy.sparse.linalg import spsolve

from .balance import support_reference
from .clip import CLIP_FPS, Clip, clip_qpos
from .g1_constants import G1
from .inverse_dynamics import InverseDynamics, finite_differences, stance_flags
from .keying import _kinematic
from .motion_plan import CLIP_SECONDS, MotionPlan, min_jerk

__all__ = ["refine"]

ITERATIONS = 40
"""Refinement iterations (the flight residuals are within the check's tolerances after about 20)."""
BAND_X = (-0.02, 0.06)
"""Lengthwise band of the single-stance CoP about the ankle [m] (the sole is about -0.05 ... +0.13)."""
BAND_Y = 0.012
"""Lateral half-band of the single-stance CoP [m] (the sole is +-0.025 at its narrowest)."""
DOUBLE_BAND = (0.04, 0.025)
"""Half-band of the CoP about the support reference in double stance (x, y) [m]."""
ZMP_OFFSET = (0.02, 0.0)
"""Support reference point in the foot frame [m]."""
F_MIN = 5.0
"""Smallest normal force of a stance frame [N]."""
FRICTION = 0.5
"""Largest |f_x| + |f_y| over the normal force the refinement allows (the check's pyramid: 0.6) [1]."""
YAW_ARM = 0.003
"""Largest yaw moment about the stance foot per newton of normal force [m]."""
HIP_CAP = 0.8 * 88.0
"""Stance hip pitch torque the refinement keeps within [N m] (the effort limit is 88)."""
W_HIP = 0.004
"""Weight of the stance hip pitch torque beyond ``HIP_CAP`` [1 / (N m)^2] (0.01 and more diverge)."""
# weights: 1 / tolerance^2 of each residual [N m], [m/s^2], [N m], and of the corrections [m], [rad]
W_MOMENT, W_ACC, W_L = 1.0, 1 / 0.03**2, 1 / 0.5**2
W_POS, W_ROT, W_SMOOTH = 1 / 0.05**2, 1 / 0.1**2, 1e-4
W_SMOOTH_ROT = 3e-3
"""Weight of the pelvis pitch and roll corrections' squared angular acceleration [s^4]."""


def base_wrench(model: mujoco.MjModel, clip: Clip) -> dict[str, np.ndarray]:
    """Per frame: the contact force the motion needs ``force`` (world) [N], its moment about the pelvis
    origin ``moment`` (world) [N m], the pelvis origin ``o``, the COM ``com`` [m] and the composite inertia
    about the COM ``inertia`` (world) [kg m^2]."""
    solver = InverseDynamics(model)
    m, d = solver.model, solver.data
    q = clip_qpos(clip)
    v, a = finite_differences(m, q, 1.0 / clip.fps)
    n, mass = len(q), mujoco.mj_getTotalmass(m)
    out = {k: np.zeros((n, 3)) for k in ("force", "moment", "o", "com")}
    out["inertia"] = np.zeros((n, 3, 3))
    out["hip_tau"], out["hip_coef"] = np.zeros(n), np.zeros((n, 3))
    stance = stance_flags(clip.contacts)
    full = np.zeros((m.nv, m.nv))
    for f in range(n):
        d.qpos[:], d.qvel[:] = q[f], v[f]
        mujoco.mj_forward(m, d)
        d.qacc[:] = a[f]
        mujoco.mj_inverse(m, d)
        rot = d.xmat[1].reshape(3, 3)
        out["force"][f], out["moment"][f] = d.qfrc_inverse[:3], rot @ d.qfrc_inverse[3:6]
        out["o"][f], out["com"][f] = d.xpos[1], d.subtree_com[1]
        mujoco.mj_fullM(m, d, full)
        r = out["com"][f] - out["o"][f]
        out["inertia"][f] = rot @ full[3:6, 3:6] @ rot.T - mass * (r @ r * np.eye(3) - np.outer(r, r))
        _stance_hip(m, d, solver, stance[f], out, f)
    out["mass"] = np.array(mass)
    return out


def _stance_hip(
    m: mujoco.MjModel, d: mujoco.MjData, solver: InverseDynamics, flags, out: dict, f: int
) -> None:
    """Single stance: the stance hip pitch torque (the foot wrench that balances the base exactly) and the
    mass, COM height above the hip and pitch inertia about the hip of the body it carries (all but the
    stance leg)."""
    if flags.sum() != 1:
        return
    leg = int(np.flatnonzero(flags)[0])
    jacp, jacr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
    mujoco.mj_jacBody(m, d, jacp, jacr, solver.feet[leg])
    jac = np.vstack([jacp, jacr])
    h = d.qfrc_inverse
    wrench = np.linalg.lstsq(jac[:, :6].T, h[:6], rcond=None)[0]
    dof = solver.dofs[6 * leg]
    link = m.jnt_bodyid[m.dof_jntid[dof]]
    mass, m_leg = m.body_subtreemass[1], m.body_subtreemass[link]
    com_up = (mass * d.subtree_com[1] - m_leg * d.subtree_com[link]) / (mass - m_leg)
    r = com_up - d.xanchor[m.dof_jntid[dof]]
    out["hip_tau"][f] = h[dof] - jac[:, dof] @ wrench
    out["hip_coef"][f] = [(mass - m_leg) * r[2], (mass - m_leg) * (r[0] ** 2 + r[2] ** 2), 1.0]


def _feet(clip: Clip) -> tuple[np.ndarray, np.ndarray]:
    idx = [G1.tracked_bodies.index(f) for f in G1.feet]
    pos = clip.body_pos_w[:, idx].astype(float)
    q = clip.body_quat_w[:, idx].astype(float)
    yaw = np.arctan2(
        2 * (q[..., 0] * q[..., 3] + q[..., 1] * q[..., 2]), 1 - 2 * (q[..., 2] ** 2 + q[..., 3] ** 2)
    )
    return pos, yaw


def _band(local: np.ndarray, fz: float, lo: tuple, hi: tuple) -> np.ndarray:
    f = max(fz, 0.0)
    return np.clip(local, np.asarray(lo) * f, np.asarray(hi) * f) - local


def _moment_errors(clip: Clip, w: dict, plan: MotionPlan) -> tuple[np.ndarray, np.ndarray]:
    """Wanted change of (CoP - o) F_z [N m] (world x, y) per frame, and the frames it applies to."""
    n = clip.frames
    flags = stance_flags(clip.contacts)
    flight = clip.contacts.sum(axis=1) == 0
    fx, fz, tau, o = w["force"], w["force"][:, 2], w["moment"], w["o"]
    pf = np.column_stack([-(tau[:, 1] + o[:, 2] * fx[:, 0]), tau[:, 0] - o[:, 2] * fx[:, 1]])
    pos, yaw = _feet(clip)
    pref = support_reference(plan, np.arange(n) / clip.fps, np.asarray(ZMP_OFFSET))
    err, rows = np.zeros((n, 2)), np.zeros(n, dtype=bool)

    def on_foot(f: int, k: int) -> np.ndarray:
        c, s = np.cos(yaw[f, k]), np.sin(yaw[f, k])
        rot = np.array([[c, -s], [s, c]])
        local = rot.T @ (pf[f] - (pos[f, k, :2] - o[f, :2]) * fz[f])  # (CoP - foot) F_z in the foot frame
        return rot @ _band(local, fz[f], (BAND_X[0], -BAND_Y), (BAND_X[1], BAND_Y))

    for f in np.flatnonzero(~flight):
        if flags[f].sum() == 1:
            err[f], rows[f] = on_foot(f, int(np.flatnonzero(flags[f])[0])), True
            continue
        nxt = clip.contacts[f + 1 : f + 4]
        single = nxt[nxt.sum(axis=1) == 1]
        if len(single):  # a lift-off follows: the CoP on the foot that stays
            err[f] = on_foot(f, int(np.flatnonzero(single[0])[0]))
        else:
            err[f] = _band(
                pf[f] - (pref[f] - o[f, :2]) * fz[f], fz[f], tuple(-np.r_[DOUBLE_BAND]), DOUBLE_BAND
            )
        rows[f] = True
    return err, rows


def corrections(model: mujoco.MjModel, clip: Clip, plan: MotionPlan) -> tuple[np.ndarray, np.ndarray, dict]:
    """Pelvis translation (T, 3) [m] and roll/pitch/yaw (T, 3) [rad] changes of one iteration."""
    n, dt = clip.frames, 1.0 / clip.fps
    w = base_wrench(model, clip)
    mass, force, com, o, inertia = float(w["mass"]), w["force"], w["com"], w["o"], w["inertia"]
    fz = force[:, 2]
    flight = clip.contacts.sum(axis=1) == 0
    stance = ~flight
    err, single = _moment_errors(clip, w, plan)
    fmin = np.where(stance, np.maximum(F_MIN - fz, 0.0), 0.0)
    # the check's friction pyramid bounds |f_x| + |f_y|: scale the horizontal force into FRICTION f_z
    ratio = np.abs(force[:, :2]).sum(axis=1) / np.maximum(FRICTION * np.maximum(fz, 0.0), 1e-9)
    fric = np.where(
        (stance & (ratio > 1))[:, None], force[:, :2] * (1 / np.maximum(ratio, 1) - 1)[:, None], 0.0
    )
    acc = np.where(flight[:, None], -force / mass, 0.0)  # wanted COM acceleration change
    acc[:, :2] += fric / mass
    acc[:, 2] += fmin / mass
    acc_rows = flight[:, None] | (np.abs(np.column_stack([fric, fmin])) > 0)
    ldot = w["moment"] - np.cross(com - o, force)  # rate of the angular momentum about the COM
    l_err = np.where(flight[:, None], -ldot, 0.0)

    tau = w["hip_tau"]
    hip_err = np.clip(tau, -HIP_CAP, HIP_CAP) - tau
    hip_rows = np.abs(hip_err) > 0
    eye = sparse.identity(n, format="csr")
    d2 = sparse.diags([1.0, -2.0, 1.0], [-1, 0, 1], shape=(n, n), format="lil") / dt**2
    d2[0, :], d2[n - 1, :] = 0.0, 0.0
    d2 = d2.tocsr()
    smooth = W_SMOOTH * (d2.T @ d2)
    zero = sparse.csr_matrix((n, n))

    def diag(v) -> sparse.csr_matrix:
        return sparse.diags(np.asarray(v, dtype=float), format="csr")

    dc, dr = np.zeros((n, 3)), np.zeros((n, 3))
    for ax, rax, sign in ((0, 1, -1.0), (1, 0, 1.0)):  # x with pitch, y with roll
        irr = diag(inertia[:, rax, rax])
        a1 = sparse.hstack([diag(fz) - mass * diag(com[:, 2]) @ d2, sign * irr @ d2])  # (CoP - o) F_z
        a2 = sparse.hstack([d2, zero])  # COM acceleration
        a3 = sparse.hstack([zero, irr @ d2])  # angular momentum rate about the rotation axis
        s, r, fl = diag(single), diag(acc_rows[:, ax]), diag(flight)
        h = W_MOMENT * a1.T @ s @ a1 + W_ACC * a2.T @ r @ a2 + W_L * a3.T @ fl @ a3
        h = h + sparse.block_diag([W_POS * eye + smooth, W_ROT * eye + W_SMOOTH_ROT / W_SMOOTH * smooth])
        g = W_MOMENT * a1.T @ s @ err[:, ax] + W_ACC * a2.T @ r @ acc[:, ax] + W_L * a3.T @ fl @ l_err[:, rax]
        if (
            ax == 0 and W_HIP > 0
        ):  # stance hip pitch torque change: -(m_up dz x'' + I theta'' - m_up g dz theta)
            cx, ci = w["hip_coef"][:, 0], w["hip_coef"][:, 1] + inertia[:, 1, 1] * (w["hip_coef"][:, 2] > 0)
            a4 = -sparse.hstack([diag(cx) @ d2, diag(ci) @ d2 - diag(9.81 * cx)])
            hr = diag(hip_rows)
            h = h + W_HIP * a4.T @ hr @ a4
            g = g + W_HIP * a4.T @ hr @ hip_err
        x = spsolve(h.tocsc(), g)
        dc[:, ax], dr[:, rax] = x[:n], x[n:]
    r = diag(acc_rows[:, 2])
    dc[:, 2] = spsolve((W_ACC * d2.T @ r @ d2 + W_POS * eye + smooth).tocsc(), W_ACC * d2.T @ r @ acc[:, 2])
    # yaw: in stance the moment about the stance foot within the sole's friction torque, in flight zero
    pos, _ = _feet(clip)
    flags = stance_flags(clip.contacts)
    for f in np.flatnonzero(stance):
        k = (
            int(np.flatnonzero(clip.contacts[f])[0])
            if clip.contacts[f].sum() == 1
            else 0
            if flags[f, 0]
            else 1
        )
        ldot[f, 2] = w["moment"][f, 2] + np.cross(o[f] - pos[f, k], force[f])[2]
    cap_z = np.where(flight, 0.0, YAW_ARM * np.maximum(fz, 0.0))
    lz = np.clip(ldot[:, 2], -cap_z, cap_z) - ldot[:, 2]
    a3 = diag(inertia[:, 2, 2]) @ d2
    near = diag(np.abs(lz) > 0)
    dr[:, 2] = spsolve((W_L * a3.T @ near @ a3 + W_ROT * eye + smooth).tocsc(), W_L * a3.T @ near @ lz)
    stats = {
        "moment": float(np.abs(err).max()),
        "acc": float(np.abs(acc).max()),
        "L": float(np.abs(l_err).max()),
    }
    return dc, dr, stats


def _moved(root, shift: np.ndarray, rot: np.ndarray, dt: float):
    """``root`` with per-frame offsets of the position and roll/pitch/yaw, linearly interpolated."""

    def f(t: float):
        pos, rpy = root(t)
        k = t / dt
        i0 = int(np.clip(np.floor(k), 0, len(shift) - 1))
        i1 = min(i0 + 1, len(shift) - 1)
        a = k - i0
        return (
            np.asarray(pos, float) + (1 - a) * shift[i0] + a * shift[i1],
            np.asarray(rpy, float) + (1 - a) * rot[i0] + a * rot[i1],
        )

    return f


def refine(
    model: mujoco.MjModel,
    plan: MotionPlan,
    seconds: float = CLIP_SECONDS,
    fps: float = CLIP_FPS,
    iterations: int | None = None,
    log=None,
) -> Clip:
    """The plan's clip keyed and refined (``corrections``, ``iterations`` times, default ``ITERATIONS``). Where a corrected pelvis
    puts a stance foot out of the IK's reach, the correction is faded out around that time and retried."""
    clip = _kinematic(model, plan, seconds, fps)
    n, dt = clip.frames, 1.0 / fps
    t = np.arange(n) * dt
    window = np.array([min_jerk((seconds - 0.1 - tt) / 1.0) for tt in t])[:, None]  # at rest at the end
    shift, rot = np.zeros((n, 3)), np.zeros((n, 3))
    for it in range(int(iterations or ITERATIONS)):
        dc, dr, stats = corrections(model, clip, plan)
        dc, dr = dc * window, dr * window
        mask = np.ones((n, 1))
        for _ in range(6):
            try:
                moved = replace(plan, root=_moved(plan.root, shift + mask * dc, rot + mask * dr, dt))
                clip = _kinematic(model, moved, seconds, fps)
            except ValueError as e:
                tf = float(str(e).split("t = ")[1].split(" s")[0])
                mask *= np.array([1 - min_jerk(1.5 - abs(tt - tf) / 0.3) for tt in t])[:, None]
                continue
            shift, rot = shift + mask * dc, rot + mask * dr
            break
        else:
            break
        if log:
            log(f"{it} {stats} dc {np.abs(dc).max(0).round(4)} dr {np.abs(dr).max(0).round(4)}")
    return clip
