"""Balancing of generated clips: the zero-moment point of a clip and the pelvis shift that puts it on
the support.

``balance`` regenerates a keyed clip with its pelvis moved horizontally so that the COM follows a
cart-table plan (``plan_com``) of the support reference (``support_reference``: the stance sole's centre in
single stance, a blend between supports in double stance); with ``MotionPlan.centroidal`` it aims the
whole-body zero-moment point (``centroidal_zmp``: vertical COM acceleration and the centroidal angular
momentum's rate included) rather than the cart-table one (``zmp_path``) at the support.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import mujoco
import numpy as np

from .clip import CLIP_FPS, Clip
from .g1_constants import G1
from .keying import _kinematic
from .motion_plan import CLIP_SECONDS, GRAVITY, MotionPlan, Stance, min_jerk

__all__ = [
    "balance",
    "centroidal_momentum",
    "centroidal_zmp",
    "plan_com",
    "support_reference",
    "zmp_path",
]


BALANCE_ITERATIONS = 6
"""Pelvis corrections of ``balance`` (the COM meets its plan within 0.1 mm after about four)."""
ZMP_WEIGHT_SINGLE = 10.0
"""Weight of the zero-moment point's distance to the support in single stance, against 1 in double
stance (where the support polygon spans both feet and the reference is only a guide) [1]."""
JERK_WEIGHT = 1e-7
"""Weight of the COM jerk [s^6] against the zero-moment point's distance [m^2]."""
COM_WEIGHT = 0.05
"""Weight keeping the COM itself near the support reference [1]."""


def sole_centre(model: mujoco.MjModel) -> np.ndarray:
    """Centre (x, y) [m] of a foot's sole capsules in its body frame (the support point of a stance)."""
    foot = model.body(G1.feet[0]).id
    geoms = [g for g in range(model.ngeom) if model.geom_bodyid[g] == foot and model.geom_conaffinity[g]]
    return model.geom_pos[geoms].mean(axis=0)[:2]


def support_reference(plan: MotionPlan, t: np.ndarray, offset: np.ndarray) -> np.ndarray:
    """(T, 2) reference of the zero-moment point [m]: the stance sole's centre in single stance; in double
    stance a minimum-jerk blend from the last support to the next, through the feet's midpoint when the
    double stance lasts longer than 1.2 s (0.5 s blends at each end)."""

    def sole(s: Stance) -> np.ndarray:
        c, sn = np.cos(s.yaw), np.sin(s.yaw)
        return np.asarray(s.xy) + np.array([c * offset[0] - sn * offset[1], sn * offset[0] + c * offset[1]])

    def on(tt: float) -> list[Stance]:
        return [s for s in plan.stances if s.t0 <= tt <= s.t1]

    def centre(tt: float) -> np.ndarray:
        return np.mean([sole(s) for s in on(tt)], axis=0)

    n = len(t)
    p = np.full((n, 2), np.nan)
    for i, tt in enumerate(t):
        now = on(tt)
        if len(now) == 1:
            p[i] = sole(now[0])
    i = 0
    while i < n:
        if not np.isnan(p[i, 0]):
            i += 1
            continue
        j = i
        while j < n and np.isnan(p[j, 0]):
            j += 1
        a = p[i - 1] if i > 0 else centre(t[i])
        b = p[j] if j < n else centre(t[j - 1])
        mid = centre(t[(i + j - 1) // 2])
        length = (j - i) * (t[1] - t[0])
        for k in range(i, j):
            u = (t[k] - t[i]) / max(length, 1e-9)
            if length > 1.2:
                e = 0.5 / length
                if u < e:
                    p[k] = a + (mid - a) * min_jerk(u / e)
                elif u > 1 - e:
                    p[k] = mid + (b - mid) * min_jerk((u - 1 + e) / e)
                else:
                    p[k] = mid
            else:
                p[k] = a + (b - a) * min_jerk(u)
        i = j
    return p


def plan_com(p: np.ndarray, dt: float, height: float, weight: np.ndarray) -> np.ndarray:
    """COM path (T,) of a cart-table model along one axis: minimises sum w (c - (h/g) c'' - p)^2
    + JERK_WEIGHT c'''^2 + COM_WEIGHT (c - p)^2 (one dense solve; T = 1001).

    Args:
        p: (T,) support reference [m]. dt: frame period [s]. height: COM height h [m].
        weight: (T,) weight of the zero-moment point term per frame.
    """
    n = len(p)
    eye = np.eye(n)
    d2 = (np.eye(n, k=1) - 2 * eye + np.eye(n, k=-1)) / dt**2
    d2[0] = d2[-1] = 0.0
    d3 = (np.eye(n, k=2) - 3 * np.eye(n, k=1) + 3 * eye - np.eye(n, k=-1))[1:-2] / dt**3
    z = eye - (height / GRAVITY) * d2
    w = np.diag(weight)
    a = z.T @ w @ z + JERK_WEIGHT * d3.T @ d3 + COM_WEIGHT * eye
    return np.linalg.solve(a, z.T @ w @ p + COM_WEIGHT * p)


def com_path(model: mujoco.MjModel, clip: Clip) -> np.ndarray:
    """(T, 3) whole-body centre of mass of a clip [m]."""
    data = mujoco.MjData(model)
    out = np.zeros((clip.frames, 3))
    for f in range(clip.frames):
        data.qpos[:] = clip.qpos(f)
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        out[f] = data.subtree_com[model.body("pelvis").id]
    return out


def zmp_path(model: mujoco.MjModel, clip: Clip) -> np.ndarray:
    """(T, 2) zero-moment point of a clip on flat ground by the cart-table model [m]: COM minus
    (h / g) times its horizontal acceleration (second differences at the clip rate)."""
    com = com_path(model, clip)
    dt = 1.0 / clip.fps
    acc = np.gradient(np.gradient(com[:, :2], dt, axis=0), dt, axis=0)
    return com[:, :2] - com[:, 2:3] / GRAVITY * acc


def centroidal_momentum(model: mujoco.MjModel, clip: Clip) -> tuple[np.ndarray, np.ndarray]:
    """(T, 3) whole-body COM [m] and (T, 3) angular momentum about it [kg m^2/s] (world; velocities by
    central differences of the clip's ``qpos``)."""
    from .clip import clip_qpos
    from .inverse_dynamics import finite_differences

    qpos = clip_qpos(clip)
    qvel, _ = finite_differences(model, qpos, 1.0 / clip.fps)
    data = mujoco.MjData(model)
    root = model.body("pelvis").id
    com, ang = np.zeros((clip.frames, 3)), np.zeros((clip.frames, 3))
    for f in range(clip.frames):
        data.qpos[:], data.qvel[:] = qpos[f], qvel[f]
        mujoco.mj_forward(model, data)
        mujoco.mj_subtreeVel(model, data)
        com[f], ang[f] = data.subtree_com[root], data.subtree_angmom[root]
    return com, ang


def centroidal_zmp(model: mujoco.MjModel, clip: Clip) -> np.ndarray:
    """(T, 2) zero-moment point on flat ground (z = 0) of the whole body [m]: the point about which the
    ground reaction's horizontal moment vanishes, from the COM c, its acceleration and the angular
    momentum L about it: p_x = c_x - (c_z c''_x + L'_y / m) / (g + c''_z), p_y = c_y - (c_z c''_y -
    L'_x / m) / (g + c''_z) (second differences at the clip rate)."""
    com, ang = centroidal_momentum(model, clip)
    dt = 1.0 / clip.fps
    acc = np.gradient(np.gradient(com, dt, axis=0), dt, axis=0)
    dang = np.gradient(ang, dt, axis=0) / mujoco.mj_getTotalmass(model)
    fz = GRAVITY + acc[:, 2]
    px = com[:, 0] - (com[:, 2] * acc[:, 0] + dang[:, 1]) / fz
    py = com[:, 1] - (com[:, 2] * acc[:, 1] - dang[:, 0]) / fz
    return np.column_stack([px, py])


def balance(
    model: mujoco.MjModel, plan: MotionPlan, clip: Clip, seconds: float = CLIP_SECONDS, fps: float = CLIP_FPS
) -> Clip:
    """The clip regenerated with its pelvis moved horizontally so that the COM follows ``plan_com`` of
    the support reference: the zero-moment point then stays on the stance sole in single stance, which a
    clip keyed on the pelvis alone does not do (the arms and the swing leg move the COM, and a keyed
    weight shift leaves it centimetres off a 5 cm wide sole). Feet, root height and orientation, and the
    upper body are unchanged."""
    n, dt = clip.frames, 1.0 / fps
    t = np.arange(n) * dt
    single = clip.contacts.sum(axis=1) == 1
    com = com_path(model, clip)
    p = support_reference(plan, t, sole_centre(model))
    w = np.where(single, ZMP_WEIGHT_SINGLE, 1.0)
    h = float(com[:, 2].mean())
    target = np.stack([plan_com(p[:, k], dt, h, w) for k in (0, 1)], axis=1)
    shift = np.zeros((n, 2))
    for _ in range(BALANCE_ITERATIONS):
        if plan.centroidal:  # aim the cart-table ZMP off the support by what it misses of the whole body's
            cart = com[:, :2] - h / GRAVITY * np.gradient(np.gradient(com[:, :2], dt, axis=0), dt, axis=0)
            miss = centroidal_zmp(model, clip) - cart
            target = np.stack([plan_com(p[:, k] - miss[:, k], dt, h, w) for k in (0, 1)], axis=1)
        shift += target - com[:, :2]
        clip = _kinematic(model, replace(plan, root=_shifted(plan.root, shift, dt)), seconds, fps)
        com = com_path(model, clip)
    return clip


def _shifted(root: Callable, shift: np.ndarray, dt: float) -> Callable:
    """``root`` with a horizontal offset interpolated from the per-frame ``shift`` (T, 2) [m]."""

    def moved(t: float):
        pos, rpy = root(t)
        k = t / dt
        i0 = int(np.clip(np.floor(k), 0, len(shift) - 1))
        i1 = min(i0 + 1, len(shift) - 1)
        a = k - i0
        pos = np.array(pos, dtype=float)
        pos[:2] += (1 - a) * shift[i0] + a * shift[i1]
        return pos, rpy

    return moved
