"""Generated reference clips in five styles: keyframes for the root and upper body, footsteps for
the feet, leg inverse kinematics for the contacts.

Each style is a ``MotionPlan``: per foot a list of stances (time interval, foothold, yaw), a root
trajectory (pelvis position and roll/pitch/yaw) and upper-body joint angles as functions of time.
Between two stances a foot swings on a minimum-jerk path with a vertical arc. Every 50 Hz frame,
``LegIK`` places the feet (stance: on the ground, flat); the clip's body poses are the forward
kinematics of the result. Run and sprint have flight phases in which the pelvis translation is
ballistic: constant horizontal velocity and ``z'' = -g``; in stance the pelvis height follows a cubic
Hermite segment joining the landing and take-off velocities.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import mujoco
import numpy as np

from .clip import CLIP_FPS, Clip
from .g1_constants import G1
from .ik import LegIK

__all__ = ["MotionPlan", "Stance", "generate", "min_jerk", "rpy_quat"]

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


def generate(
    model: mujoco.MjModel, plan: MotionPlan, seconds: float = CLIP_SECONDS, fps: float = CLIP_FPS
) -> Clip:
    """The clip of a plan (``model``: the free-base G1).

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
            for k in range(a + 1, b):
                u = (k - a) / (b - a)
                qpos[k, cols] = (1 - min_jerk(u)) * qpos[a, cols] + min_jerk(u) * qpos[b, cols]
                qpos[k, cols] += (4 * u * (1 - u)) ** 1.5 * bump
            i = b
    qpos[:, 7:] = np.clip(qpos[:, 7:], ik.lo, ik.hi)
    return Clip.from_qpos(model, qpos, contacts, fps)
