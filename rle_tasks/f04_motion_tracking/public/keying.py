"""Kinematic keying of a motion plan into a clip: leg inverse kinematics for the stances, joint-space
swings between them.

Every 50 Hz frame the plan's root and upper-body angles are set and ``LegIK`` places the stance feet (on
the ground, flat); a swing leg then moves in joint space from its lift-off to its touchdown solution, on a
minimum-jerk blend plus a flexion bump that clears the ground, or (``MotionPlan.matched_swing``) on a
quintic Hermite that meets the stance solutions' velocities and accelerations. The clip's body poses are
the forward kinematics of the result.
"""

from __future__ import annotations

import mujoco
import numpy as np

from .clip import CLIP_FPS, Clip
from .g1_constants import G1
from .ik import LegIK, foot_quat
from .motion_plan import CLIP_SECONDS, MotionPlan, min_jerk, rpy_quat

__all__ = ["TOE", "foot_ground_height"]

TOE = 0.13
"""Toe line of the sole (its polygon's front edge) ahead of the foot body's origin [m]."""
SWING_KNEE_MIN = 0.3
"""Smallest knee angle of a swing leg on a world path [rad] (keeps it off the straight-knee singularity)."""
HEEL_RISE_STANCES = 0.5
"""``MotionPlan.heel_rise`` applies to stances shorter than this [s] (running steps, not standing)."""


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
            dur, angle = plan.heel_rise
            if dur > 0 and s is not own[-1] and s.t1 - s.t0 < HEEL_RISE_STANCES and t > s.t1 - dur:
                pos, yaw, pitch = _on_toes(s, z0, angle * min_jerk((t - s.t1 + dur) / dur))
                return pos, yaw, True, pitch
            return np.array([*s.xy, z0]), s.yaw, True
        if s.t1 < t:
            prev = s
        elif prev is not None:  # swing from prev to s
            b = min_jerk((t - prev.t1) / (s.t0 - prev.t1))
            u = (t - prev.t1) / (s.t0 - prev.t1)
            if plan.cartesian_swing:  # world path from the lift-off pose (toes) to the foothold (flat)
                dur, angle = plan.heel_rise
                rises = dur > 0 and prev.t1 - prev.t0 < HEEL_RISE_STANCES
                start, _, pitch = _on_toes(prev, z0, angle if rises else 0.0)
                bump = (4 * u * (1 - u)) ** plan.bump_power
                apex = plan.swing_height if s.apex is None else s.apex
                pos = (1 - b) * start + b * np.array([*s.xy, z0]) + np.array([0.0, 0.0, apex * bump])
                return pos, (1 - b) * prev.yaw + b * s.yaw, False, (1 - b) * pitch
            bump = (4 * u * (1 - u)) ** 1.5
            xy = (1 - b) * np.asarray(prev.xy) + b * np.asarray(s.xy) + bump * np.asarray(s.via)
            z = z0 + (plan.swing_height if s.apex is None else s.apex) * bump
            return np.array([*xy, z]), (1 - b) * prev.yaw + b * s.yaw, False
        else:
            return np.array([*s.xy, z0]), s.yaw, True
    last = own[-1]
    return np.array([*last.xy, z0]), last.yaw, True


def _on_toes(s, z0: float, pitch: float) -> tuple[np.ndarray, float, float]:
    """Foot origin, yaw and pitch of stance ``s`` pivoted by ``pitch`` on its toe line (which stays put)."""
    toe_local = np.array([TOE, 0.0, -z0])
    flat = np.array([*s.xy, z0])
    toe = flat + _quat_rot(foot_quat(s.yaw)) @ toe_local
    return toe - _quat_rot(foot_quat(s.yaw, pitch)) @ toe_local, s.yaw, pitch


def _quat_rot(q: np.ndarray) -> np.ndarray:
    out = np.zeros(9)
    mujoco.mju_quat2Mat(out, q)
    return out.reshape(3, 3)


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
        if plan.cartesian_swing:
            q, worst = ik.solve(q, targets, swing_iters=50, swing_knee_min=SWING_KNEE_MIN)
        else:
            q, worst = ik.solve(q, [tg if tg[2] else None for tg in targets])
        if worst > 1e-4:
            raise ValueError(f"t = {t:.2f} s: stance foot {worst * 1e3:.2f} mm from its foothold")
        qpos[i] = q
    for leg in () if plan.cartesian_swing else (0, 1):
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
                if not plan.swing_acc:
                    end = (end[0], end[1], 0 * end[2], end[3], end[4], 0 * end[5])
            for k in range(a + 1, b):
                u = (k - a) / m
                if plan.matched_swing:
                    qpos[k, cols] = _quintic(u, m, *end) + (4 * u * (1 - u)) ** plan.bump_power * bump
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
