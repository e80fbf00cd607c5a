"""Motion plans of the clip generator: what a generated clip is keyed from, and the keying primitives.

A ``MotionPlan`` holds per foot a list of ``Stance``s (time interval, foothold, yaw, and the apex and
detour of the swing that lands there), a root trajectory (pelvis position and roll/pitch/yaw) and
upper-body joint angles as functions of time, with the generator's options (balancing, matched swings,
the whole-body zero-moment point). The primitives are the minimum-jerk blend and keyframe interpolation
the styles key their trajectories with, and the roll/pitch/yaw quaternion of the root.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import mujoco
import numpy as np

from .g1_constants import G1

__all__ = ["MotionPlan", "Stance", "keyed", "min_jerk", "rpy_quat"]

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
    bump_power: float = 3.0
    """Exponent p of a matched swing's flexion bump (4u(1-u))^p (3: zero slope and curvature at the ends)."""
    swing_acc: bool = True
    """A matched swing meets the stance joints' accelerations at its ends too (False: zero accelerations; the
    stance legs' accelerations of a run ask the swing hip pitch for several times its limit)."""
    cartesian_swing: bool = False
    """Swing feet on world paths solved by the leg IK (minimum jerk from the lift-off pose, apex bump
    (4u(1-u))^bump_power, pitch fading to flat; knee at least ``keying.SWING_KNEE_MIN``) instead of
    joint-space blends: the foot leaves and lands at rest and cannot pass through the floor (not yet used by
    a shipped clip: README, Clip feasibility)."""
    heel_rise: tuple[float, float] = (0.0, 0.0)
    """(duration [s], angle [rad]): over the last ``duration`` of a stance before a lift-off the foot pivots
    on its toe line (``TOE``) up to ``angle`` (minimum jerk), heel up; (0, 0): flat until lift-off."""
    refine: Callable | None = None
    """Run and sprint: ``(model, plan) -> Clip`` that replaces balancing (``run_refine.refine``)."""
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
