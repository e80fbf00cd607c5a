"""Generated reference clips in five styles: keyframes for the root and upper body, footsteps for
the feet, leg inverse kinematics for the contacts.

Each style is a ``MotionPlan``: per foot a list of stances (time interval, foothold, yaw), a root
trajectory (pelvis position and roll/pitch/yaw) and upper-body joint angles as functions of time.
Between two stances a foot swings on a minimum-jerk path with a vertical arc. Every 50 Hz frame,
``LegIK`` places the feet (stance: on the ground, flat); the clip's body poses are the forward
kinematics of the result. Run and sprint have flight phases in which the pelvis translation is
ballistic: constant horizontal velocity and ``z'' = -g``; in stance the pelvis height follows a cubic
Hermite segment joining the landing and take-off velocities. Plans that stay on their feet (dance,
fight, fall-getup) are then balanced: the pelvis is moved so that the zero-moment point stays on the stance sole
(``balance``), which makes the clip physically trackable.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import mujoco
import numpy as np

from .clip import CLIP_FPS, Clip
from .g1_constants import G1
from .ik import LegIK

__all__ = [
    "MotionPlan",
    "Stance",
    "balance",
    "centroidal_momentum",
    "centroidal_zmp",
    "generate",
    "min_jerk",
    "plan_com",
    "rpy_quat",
    "support_reference",
    "zmp_path",
]

GRAVITY = 9.81
"""[m/s^2]"""
CLIP_SECONDS = 20.0
"""Length of every generated clip [s]."""
STAND_Z = G1.default_height
HIP_Y = 0.118
"""Lateral foot offset of the default pose [m]."""


@dataclass(frozen=True)
class Stance:
    """One foot on the ground from ``t0`` to ``t1`` [s] at ``xy`` [m] with heading ``yaw`` [rad]."""

    foot: int
    t0: float
    t1: float
    xy: tuple[float, float]
    yaw: float = 0.0
    apex: float | None = None
    """Apex height [m] of the swing that lands on this stance (None: the plan's ``swing_height``)."""
    via: tuple[float, float] = (0.0, 0.0)
    """Horizontal detour [m] of that swing at mid-swing (a kick reaches forward and comes back)."""


@dataclass(frozen=True)
class MotionPlan:
    """What the generator turns into a clip."""

    stances: tuple[Stance, ...]
    root: Callable[[float], tuple[np.ndarray, np.ndarray]]
    """t -> pelvis position (3,) [m], roll/pitch/yaw (3,) [rad]."""
    upper: Callable[[float], dict[str, float]]
    """t -> angles [rad] of non-leg joints (unlisted: default pose)."""
    swing_height: float = 0.08
    """Apex of a swing above the ground [m]."""
    balanced: bool = False
    """Move the pelvis horizontally so that the zero-moment point stays on the support (``balance``);
    for plans whose only contacts are the feet and that never leave the ground (dance, fight, fall-getup)."""
    matched_swing: bool = False
    """Swing legs leave and reach their stance solutions with the stance joints' velocities and accelerations
    (quintic Hermite in joint space, flexion bump (4u(1-u))^3) instead of at rest: the foot's world velocity
    and acceleration are continuous at lift-off and touchdown."""
    centroidal: bool = False
    """``balance`` aims the whole-body zero-moment point (``centroidal_zmp``: vertical COM acceleration and
    the centroidal angular momentum's rate included) at the support, not the cart-table one."""


def min_jerk(s: float) -> float:
    """Minimum-jerk blend 10 s^3 - 15 s^4 + 6 s^5 of s in [0, 1] (clipped)."""
    s = min(max(s, 0.0), 1.0)
    return s**3 * (10 - 15 * s + 6 * s * s)


def keyed(t: float, keys: list[tuple[float, np.ndarray | float]]) -> np.ndarray:
    """Minimum-jerk interpolation through ``(time, value)`` keys (held before the first, after the last)."""
    if t <= keys[0][0]:
        return np.asarray(keys[0][1], dtype=float)
    for (t0, v0), (t1, v1) in zip(keys, keys[1:]):
        if t <= t1:
            b = min_jerk((t - t0) / (t1 - t0))
            return (1 - b) * np.asarray(v0, dtype=float) + b * np.asarray(v1, dtype=float)
    return np.asarray(keys[-1][1], dtype=float)


def rpy_quat(rpy: np.ndarray) -> np.ndarray:
    """Quaternion (w x y z) of ``R = Rz(yaw) Ry(pitch) Rx(roll)``."""
    r, p, y = (float(v) / 2 for v in rpy)
    qx = np.array([np.cos(r), np.sin(r), 0, 0])
    qy = np.array([np.cos(p), 0, np.sin(p), 0])
    qz = np.array([np.cos(y), 0, 0, np.sin(y)])
    out, tmp = np.zeros(4), np.zeros(4)
    mujoco.mju_mulQuat(tmp, qz, qy)
    mujoco.mju_mulQuat(out, tmp, qx)
    return out


def foot_ground_height(model: mujoco.MjModel) -> float:
    """Height of a foot body's origin [m] when its sole capsules rest on the floor (flat foot)."""
    foot = model.body(G1.feet[0]).id
    lows = [
        model.geom_pos[g][2] - model.geom_size[g][0]
        for g in range(model.ngeom)
        if model.geom_bodyid[g] == foot and model.geom_contype[g] + model.geom_conaffinity[g] > 0
    ]
    return -float(min(lows))


def _foot_target(plan: MotionPlan, foot: int, t: float, z0: float) -> tuple[np.ndarray, float, bool]:
    own = [s for s in plan.stances if s.foot == foot]
    prev = None
    for s in own:
        if s.t0 <= t <= s.t1:
            return np.array([*s.xy, z0]), s.yaw, True
        if s.t1 < t:
            prev = s
        elif prev is not None:  # swing from prev to s
            b = min_jerk((t - prev.t1) / (s.t0 - prev.t1))
            u = (t - prev.t1) / (s.t0 - prev.t1)
            bump = (4 * u * (1 - u)) ** 1.5
            xy = (1 - b) * np.asarray(prev.xy) + b * np.asarray(s.xy) + bump * np.asarray(s.via)
            z = z0 + (plan.swing_height if s.apex is None else s.apex) * bump
            return np.array([*xy, z]), (1 - b) * prev.yaw + b * s.yaw, False
        else:
            return np.array([*s.xy, z0]), s.yaw, True
    last = own[-1]
    return np.array([*last.xy, z0]), last.yaw, True


def _swing_offset(apex: float, via_x: float) -> np.ndarray:
    """Leg joint offsets (hip pitch, hip roll, hip yaw, knee, ankle pitch, ankle roll) [rad] at mid-swing
    that lift the foot about ``apex`` [m] and reach ``via_x`` [m] forward (a kick)."""
    return np.array([-2.5 * apex - 2.0 * via_x, 0.0, 0.0, 5.0 * apex - 3.0 * via_x, -2.5 * apex, 0.0])


def _kinematic(
    model: mujoco.MjModel, plan: MotionPlan, seconds: float = CLIP_SECONDS, fps: float = CLIP_FPS
) -> Clip:
    """The clip of a plan as keyed (``model``: the free-base G1).

    Stance legs are solved frame by frame (warm-started within a stance, from the default pose at its
    first frame). A swing leg moves in joint space from its lift-off angles to its touchdown angles on a
    minimum-jerk blend plus a flexion bump (``_swing_offset``) that clears the ground.

    Raises:
        ValueError: A stance foot could not be placed within 0.1 mm (the plan is out of reach).
    """
    ik = LegIK(model)
    z0 = foot_ground_height(model)
    n = int(round(seconds * fps)) + 1
    qpos = np.zeros((n, model.nq))
    contacts = np.zeros((n, 2), dtype=bool)
    q = np.zeros(model.nq)
    q[7:] = G1.default_pose
    for i in range(n):
        t = i / fps
        pos, rpy = plan.root(t)
        q[:3], q[3:7] = pos, rpy_quat(rpy)
        upper = plan.upper(t)
        for j, name in enumerate(G1.joints[12:], start=12):
            q[7 + j] = upper.get(name.removesuffix("_joint"), G1.default_pose[j])
        targets = [_foot_target(plan, f, t, z0) for f in (0, 1)]
        contacts[i] = [tg[2] for tg in targets]
        for leg in (0, 1):
            if contacts[i, leg] and (i == 0 or not contacts[i - 1, leg]):
                q[7 + 6 * leg : 13 + 6 * leg] = G1.default_pose[6 * leg : 6 * leg + 6]
        q, worst = ik.solve(q, [tg if tg[2] else None for tg in targets])
        if worst > 1e-4:
            raise ValueError(f"t = {t:.2f} s: stance foot {worst * 1e3:.2f} mm from its foothold")
        qpos[i] = q
    for leg in (0, 1):
        cols = slice(7 + 6 * leg, 13 + 6 * leg)
        i = 0
        while i < n:
            if contacts[i, leg]:
                i += 1
                continue
            a = i - 1  # last stance frame (the clips start in stance)
            b = i
            while b < n and not contacts[b, leg]:
                b += 1
            b = min(b, n - 1)
            land = [s for s in plan.stances if s.foot == leg and s.t0 >= (a + 1) / fps - 1e-9][0]
            apex = plan.swing_height if land.apex is None else land.apex
            bump = _swing_offset(apex, land.via[0])
            m = b - a
            if plan.matched_swing:
                end = _quintic_ends(qpos[:, cols], a, b)
            for k in range(a + 1, b):
                u = (k - a) / m
                if plan.matched_swing:
                    qpos[k, cols] = _quintic(u, m, *end) + (4 * u * (1 - u)) ** 3 * bump
                else:
                    qpos[k, cols] = (1 - min_jerk(u)) * qpos[a, cols] + min_jerk(u) * qpos[b, cols]
                    qpos[k, cols] += (4 * u * (1 - u)) ** 1.5 * bump
            i = b
    qpos[:, 7:] = np.clip(qpos[:, 7:], ik.lo, ik.hi)
    return Clip.from_qpos(model, qpos, contacts, fps)


def _quintic_ends(q: np.ndarray, a: int, b: int) -> tuple[np.ndarray, ...]:
    """Positions, velocities and accelerations (per frame) of the stance solutions at lift-off frame ``a``
    and touchdown frame ``b`` of ``q`` (T, k), by one-sided second-order differences (a stance of at least
    three frames on each side; fewer frames: lower order)."""
    n = len(q)
    a1, a2 = max(a - 1, 0), max(a - 2, 0)
    b1, b2 = min(b + 1, n - 1), min(b + 2, n - 1)
    acc0 = q[a] - 2 * q[a1] + q[a2]
    acc1 = q[b2] - 2 * q[b1] + q[b]
    return q[a], q[a] - q[a1] + 0.5 * acc0, acc0, q[b], q[b1] - q[b] - 0.5 * acc1, acc1


def _quintic(
    u: float,
    m: int,
    p0: np.ndarray,
    v0: np.ndarray,
    a0: np.ndarray,
    p1: np.ndarray,
    v1: np.ndarray,
    a1: np.ndarray,
) -> np.ndarray:
    """Quintic Hermite at ``u`` in [0, 1] over ``m`` frames meeting positions, per-frame velocities and
    accelerations at both ends."""
    u2, u3, u4, u5 = u * u, u**3, u**4, u**5
    h0 = 1 - 10 * u3 + 15 * u4 - 6 * u5
    h1 = u - 6 * u3 + 8 * u4 - 3 * u5
    h2 = 0.5 * (u2 - 3 * u3 + 3 * u4 - u5)
    h3 = 0.5 * (u3 - 2 * u4 + u5)
    h4 = -4 * u3 + 7 * u4 - 3 * u5
    return h0 * p0 + (1 - h0) * p1 + m * (h1 * v0 + h4 * v1) + m * m * (h2 * a0 + h3 * a1)


def generate(
    model: mujoco.MjModel, plan: MotionPlan, seconds: float = CLIP_SECONDS, fps: float = CLIP_FPS
) -> Clip:
    """The clip of a plan (``model``: the free-base G1), balanced (``balance``) when ``plan.balanced``.

    Raises:
        ValueError: A stance foot could not be placed within 0.1 mm (the plan is out of reach).
    """
    clip = _kinematic(model, plan, seconds, fps)
    return balance(model, plan, clip, seconds, fps) if plan.balanced else clip


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
    from .feasibility import finite_differences

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
