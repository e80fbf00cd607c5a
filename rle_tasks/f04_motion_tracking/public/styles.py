"""The five motion styles of family 04 as ``MotionPlan``s (dance, fight, fall-getup, run, sprint).

Every plan starts and ends in the default standing pose. Root heights, step timings and amplitudes
are chosen inside the G1's reach and joint ranges (the generator refuses a stance it cannot place).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .motion_plan import CLIP_SECONDS, GRAVITY, HIP_Y, STAND_Z, MotionPlan, Stance, keyed, min_jerk

__all__ = ["GAITS", "STYLES", "plan_for", "refined_plan"]

TAU = 2 * math.pi
Z_WALK = 0.74
"""Pelvis touchdown height of the slowest running step [m] (the fastest uses the gait's ``z_run``)."""
ZS_POWER = 2.0
"""Dynamic gait: touchdown height z_run + (Z_WALK - z_run) (1 - v / v_max)^ZS_POWER."""


def _stances(init: list[tuple[float, float]], steps: list[tuple], end: float = CLIP_SECONDS) -> tuple:
    """Stances from footsteps ``(foot, lift, land, xy[, yaw, apex, via])`` starting from ``init``."""
    out, start, last = [], [0.0, 0.0], [tuple(init[0]), tuple(init[1])]
    yaw = [0.0, 0.0]
    extra: list[dict] = [{}, {}]
    for foot, lift, land, xy, *rest in sorted(steps, key=lambda s: s[1]):
        out.append(Stance(foot, start[foot], lift, last[foot], yaw[foot], **extra[foot]))
        yaw[foot] = rest[0] if rest else 0.0
        extra[foot] = {}
        if len(rest) > 1:
            extra[foot] = {"apex": rest[1], "via": rest[2] if len(rest) > 2 else (0.0, 0.0)}
        start[foot], last[foot] = land, tuple(xy)
    for foot in (0, 1):
        out.append(Stance(foot, start[foot], end + 1.0, last[foot], yaw[foot], **extra[foot]))
    return tuple(out)


def _feet_center(stances, t: float) -> np.ndarray:
    """Mean foothold of the feet's current (or last) stances."""
    xy = []
    for foot in (0, 1):
        own = [s for s in stances if s.foot == foot and s.t0 <= t + 1e-9]
        xy.append(own[-1].xy)
    return np.mean(np.asarray(xy), axis=0)


def _shift_keys(stances, steps, base_z: float, lean: float) -> list:
    """Root keys: over the feet, leaning over the stance foot while the other swings."""
    keys = [(0.0, np.array([*_feet_center(stances, 0.0), base_z]))]
    for foot, lift, land, *_ in sorted(steps, key=lambda s: s[1]):
        other = [s for s in stances if s.foot == 1 - foot and s.t0 <= lift <= s.t1][0]
        c = _feet_center(stances, lift - 0.5)
        over = c + lean * (np.asarray(other.xy) - c)
        keys += [(lift - 0.45, np.array([*c, base_z])), (lift - 0.05, np.array([*over, base_z]))]
        keys += [(land + 0.05, np.array([*over, base_z]))]
        keys += [(land + 0.45, np.array([*_feet_center(stances, land + 0.1), base_z]))]
    return keys


def dance() -> MotionPlan:
    y = HIP_Y
    steps = []
    for k, t in enumerate(np.arange(1.5, 18.0, 2.2)):
        foot = k % 2
        side = 1 if foot == 0 else -1
        out = (0.06 * ((k // 2) % 2), side * (y + 0.08))
        home = (0.0, side * y)
        target = out if (k // 2) % 2 == 0 else home
        steps.append((foot, t, t + 0.45, target if k % 4 < 2 else home))
    stances = _stances([(0.0, y), (0.0, -y)], steps)
    keys = _shift_keys(stances, steps, 0.0, 0.55)

    def root(t: float):
        xy = keyed(t, keys)[:2]
        z = STAND_Z - 0.03 - 0.025 * (1 - math.cos(TAU * 1.0 * t)) * min_jerk(t) * min_jerk(20 - t)
        rpy = np.array(
            [0.04 * math.sin(TAU * t / 2.2), 0.05 * math.sin(TAU * t / 3.0), 0.3 * math.sin(TAU * t / 5.5)]
        )
        return np.array([*xy, z]), rpy * min_jerk(t) * min_jerk(20 - t)

    def upper(t: float) -> dict[str, float]:
        e = min_jerk(t) * min_jerk(20 - t)
        a = math.sin(TAU * t / 2.2)
        b = math.sin(TAU * t / 2.2 + 1.2)
        return {
            "waist_yaw": -0.35 * math.sin(TAU * t / 5.5) * e,
            "waist_roll": 0.08 * math.sin(TAU * t / 4.4) * e,
            "left_shoulder_pitch": 0.2 - 1.2 * e * (0.5 + 0.5 * a),
            "left_shoulder_roll": 0.2 + 0.9 * e * (0.5 + 0.5 * b),
            "left_elbow": 0.6 + 0.6 * e * b,
            "right_shoulder_pitch": 0.2 - 1.2 * e * (0.5 - 0.5 * a),
            "right_shoulder_roll": -0.2 - 0.9 * e * (0.5 - 0.5 * b),
            "right_elbow": 0.6 - 0.6 * e * b,
            "left_wrist_roll": 0.5 * e * a,
            "right_wrist_roll": -0.5 * e * a,
        }

    return MotionPlan(
        stances, root, upper, swing_height=0.08, balanced=True, matched_swing=True, centroidal=True
    )


KICKS = (10.5, 17.5)
"""Start times of the fight clip's front kicks [s]."""


def fight() -> MotionPlan:
    y = HIP_Y
    guard = [(0.10, y + 0.04), (-0.12, -y - 0.04)]
    steps = [(1, 0.8, 1.3, guard[1]), (0, 2.0, 2.4, guard[0])]
    for t in (6.0, 13.0):  # shuffle forward and back
        steps += [
            (0, t, t + 0.35, (guard[0][0] + 0.1, guard[0][1])),
            (1, t + 0.9, t + 1.25, (guard[1][0] + 0.1, guard[1][1])),
        ]
        steps += [(1, t + 2.4, t + 2.75, guard[1]), (0, t + 3.3, t + 3.65, guard[0])]
    for t in KICKS:  # front kick with the rear (right) leg: out and back to the same foothold
        steps.append((1, t, t + 0.9, guard[1], 0.0, 0.32, (0.45, 0.08)))
    stances = _stances([(0.0, y), (0.0, -y)], steps)
    keys = _shift_keys(stances, steps, 0.0, 0.6)

    def root(t: float):
        xy = keyed(t, keys)[:2]
        crouch = min_jerk((t - 0.3) / 1.0) * min_jerk(19.5 - t)
        z = STAND_Z - 0.07 * crouch
        kick = sum(min_jerk((t - k + 0.3) / 0.3) * min_jerk((k + 1.0 - t) / 0.3) for k in KICKS)
        rpy = np.array(
            [0.0, 0.12 * crouch - 0.2 * kick, -0.25 * crouch + 0.08 * math.sin(TAU * t / 1.6) * crouch]
        )
        return np.array([*xy, z]), rpy

    def upper(t: float) -> dict[str, float]:
        g = min_jerk((t - 0.3) / 1.0) * min_jerk(19.5 - t)
        out = {
            "waist_yaw": 0.2 * g,
            "left_shoulder_pitch": 0.2 - 0.6 * g,
            "left_shoulder_roll": 0.2 + 0.1 * g,
            "left_elbow": 0.6 + 1.0 * g,
            "right_shoulder_pitch": 0.2 - 0.6 * g,
            "right_shoulder_roll": -0.2 - 0.1 * g,
            "right_elbow": 0.6 + 1.0 * g,
        }
        for i, tp in enumerate(np.arange(3.0, 19.0, 0.9)):  # jab, cross alternately; no punch while kicking
            if any(k - 0.4 < tp < k + 1.2 for k in KICKS):
                continue
            s = min_jerk((t - tp) / 0.15) * min_jerk((tp + 0.4 - t) / 0.2)
            side = "left" if i % 2 == 0 else "right"
            out[f"{side}_shoulder_pitch"] += -1.0 * s
            out[f"{side}_elbow"] += -1.35 * s
            out["waist_yaw"] += (-0.35 if side == "right" else 0.2) * s
        return out

    return MotionPlan(stances, root, upper, swing_height=0.07, balanced=True)


def fall_getup() -> MotionPlan:
    y = HIP_Y
    steps = [
        (0, 14.2, 14.6, (-0.15, y)),
        (1, 15.0, 15.4, (-0.15, -y)),
        (1, 17.2, 17.6, (0.0, -y)),
        (0, 18.0, 18.4, (0.0, y)),
    ]
    stances = _stances([(0.0, y), (0.0, -y)], steps)
    shift = _shift_keys(stances, steps, 0.0, 0.55)
    # (t, pelvis z, pelvis x offset, pitch): fast drops to a deep crouch (0.8 s and 1.1 s: the waist pitch
    # stops the torso within 0.84 of its effort limit), held, slow rises
    body = [
        (0.0, STAND_Z, 0.0, 0.0),
        (1.5, STAND_Z, 0.0, 0.0),
        (2.3, 0.50, -0.06, 0.65),
        (4.5, 0.48, -0.07, 0.7),
    ]
    body += [
        (6.2, STAND_Z - 0.01, 0.0, 0.0),
        (7.5, STAND_Z, 0.0, 0.0),
        (8.1, 0.53, -0.05, 0.55),
        (8.6, 0.47, -0.07, 0.75),
    ]
    body += [(10.5, 0.47, -0.07, 0.75), (12.5, STAND_Z, 0.0, 0.0), (20.0, STAND_Z, 0.0, 0.0)]
    keys = [(t, np.array([z, x, p])) for t, z, x, p in body]

    def root(t: float):
        z, dx, pitch = keyed(t, keys)
        xy = keyed(t, shift)[:2] + np.array([dx, 0.0])
        return np.array([*xy, z]), np.array([0.0, pitch, 0.0])

    def upper(t: float) -> dict[str, float]:
        low = (STAND_Z - keyed(t, keys)[0]) / (STAND_Z - 0.47)
        return {
            "waist_pitch": 0.25 * low,
            "left_shoulder_pitch": 0.2 - 1.3 * low,
            "right_shoulder_pitch": 0.2 - 1.3 * low,
            "left_shoulder_roll": 0.2 + 0.1 * low,
            "right_shoulder_roll": -0.2 - 0.1 * low,
            "left_elbow": 0.6 - 0.5 * low,
            "right_elbow": 0.6 - 0.5 * low,
        }

    return MotionPlan(
        stances, root, upper, swing_height=0.07, balanced=True, matched_swing=True, centroidal=True
    )


def _gait(
    v_max: float,
    step_time: float,
    stance_time: float,
    z_run: float,
    lean: float,
    apex: float,
    arm: float,
    width: float = 0.10,
    dynamic: bool = False,
    plant: float = 0.5,
) -> MotionPlan:
    """Running gait: alternating steps, speed ramped up over 6 steps and down over the last 6; footholds
    ``width`` [m] either side of the midline; in stance the pelvis height is a cubic Hermite from landing to
    take-off. ``dynamic`` (``run_refine``): the stance pelvis height follows a half-sine vertical force
    (``_sine_stance``), the speed ramps down over 12 steps (braking puts the foot ahead of the COM, at the
    edge of the leg's reach), the last stance brings the pelvis to rest, the swings are velocity-matched and
    the clip is refined (``run_refine.refine``). ``plant``: at full speed the pelvis passes a foothold at
    this fraction of the stance (0.5 down to it with the speed)."""
    t0, n, ramp, y = 1.0, 0, 6, width
    times = []
    t = t0
    while t < CLIP_SECONDS - 2.0:
        times.append(t)
        t += step_time
    n = len(times)
    down = 2 * ramp if dynamic else ramp
    v = [v_max * min(1.0, (k + 1) / ramp, (n - k) / down) for k in range(n)]
    ts = [stance_time + (1 - vk / v_max) * (1.25 * step_time - stance_time) for vk in v]
    flight = [max(step_time - s, 0.0) for s in ts]
    v0 = [GRAVITY * f / 2 for f in flight]  # take-off vertical speed of a ballistic flight of that length
    zs = [Z_WALK + (z_run - Z_WALK) * vk / v_max for vk in v]  # touchdown heights: lower when faster
    if dynamic:  # the pelvis stays low until the gait is slow (a high one lands with a straight knee)
        zs = [z_run + (Z_WALK - z_run) * (1 - vk / v_max) ** ZS_POWER for vk in v]
    # pelvis horizontal velocity and height, sampled at 1 ms and integrated
    dt = 1e-3
    grid = np.arange(0.0, CLIP_SECONDS + 2 * dt, dt)
    vel, z = np.zeros_like(grid), np.zeros_like(grid)
    for i, tt in enumerate(grid):
        k = int(np.searchsorted(times, tt, side="right")) - 1
        if k < 0:
            vel[i], z[i] = 0.0, STAND_Z + (Z_WALK - STAND_Z) * min_jerk(tt / t0)
            continue
        tau = tt - times[k]
        vprev, v0prev, zprev = (v[k - 1], v0[k - 1], zs[k - 1]) if k > 0 else (0.0, 0.0, Z_WALK)
        if k >= n - 1 and tau > ts[k]:
            vel[i] = 0.0
            z[i] = zs[k] + (STAND_Z - zs[k]) * min_jerk((tau - ts[k]) / 1.0)
            continue
        if tau <= ts[k]:  # stance: velocities blend, height is a cubic Hermite from landing to take-off
            s = tau / ts[k]
            vel[i] = vprev + ((0.0 if dynamic and k == n - 1 else v[k]) - vprev) * min_jerk(s)
            h00, h10, h01, h11 = (
                2 * s**3 - 3 * s**2 + 1,
                s**3 - 2 * s**2 + s,
                -2 * s**3 + 3 * s**2,
                s**3 - s**2,
            )
            z[i] = h00 * zprev + h01 * zs[k] + (h10 * -v0prev + h11 * v0[k]) * ts[k]
            if dynamic:
                z[i] = _sine_stance(tau, ts[k], zprev, v0prev, zs[k], v0[k])
        else:  # flight: ballistic
            f = tau - ts[k]
            vel[i] = v[k]
            z[i] = zs[k] + v0[k] * f - 0.5 * GRAVITY * f * f
    x = np.concatenate([[0.0], np.cumsum(0.5 * (vel[1:] + vel[:-1]) * dt)])

    def x_at(tt: float) -> float:
        return float(np.interp(tt, grid, x))

    steps = []
    for k in range(n):
        foot = k % 2
        land = times[k]
        prev_end = times[k - 2] + ts[k - 2] if k >= 2 else land - 0.35
        xy = (x_at(land + (0.5 - (0.5 - plant) * v[k] / v_max) * ts[k]), y if foot == 0 else -y)
        steps.append((foot, prev_end, land, xy))
    stop = times[n - 1] + ts[n - 1]  # the pelvis stops at the end of the last stance
    side = {0: y, 1: -y}
    steps.append((n % 2, times[n - 2] + ts[n - 2], stop, (x_at(stop), side[n % 2])))
    steps.append(((n - 1) % 2, stop + 0.3, stop + 0.7, (x_at(stop), side[(n - 1) % 2])))
    stances = _stances([(0.0, y), (0.0, -y)], steps)

    def root(tt: float):
        speed = float(np.interp(tt, grid, vel)) / v_max
        roll = 0.03 * math.sin(math.pi * (tt - t0) / step_time) * speed
        return np.array([x_at(tt), 0.0, float(np.interp(tt, grid, z))]), np.array([roll, lean * speed, 0.0])

    def upper(tt: float) -> dict[str, float]:
        speed = float(np.interp(tt, grid, vel)) / v_max
        swing = arm * speed * math.cos(math.pi * (tt - t0) / step_time)
        return {
            "left_shoulder_pitch": 0.2 + swing,
            "right_shoulder_pitch": 0.2 - swing,
            "left_elbow": 0.6 + (1.2 - 0.6) * speed,
            "right_elbow": 0.6 + (1.2 - 0.6) * speed,
            "waist_yaw": -0.15 * swing,
        }

    if not dynamic:
        return MotionPlan(stances, root, upper, swing_height=apex)
    from .run_refine import refine

    return MotionPlan(
        stances,
        root,
        upper,
        swing_height=apex,
        matched_swing=True,
        bump_power=2.0,
        swing_acc=False,
        refine=refine,
    )


def _sine_stance(tau: float, ts: float, z0: float, v_land: float, z1: float, v_off: float) -> float:
    """Height at ``tau`` of a stance of ``ts`` [s] landing at ``z0`` falling at ``v_land`` and taking off at
    ``z1`` rising at ``v_off`` [m, m/s], under a half-sine vertical force z'' = -g + A sin(pi tau / ts),
    A = pi (v_off + v_land + g ts) / (2 ts) (zero force at touchdown and take-off, the take-off speed met),
    plus a minimum-jerk blend of what that leaves of z1 (zero in a steady gait)."""
    a = math.pi * (v_off + v_land + GRAVITY * ts) / (2 * ts)

    def free(t: float) -> float:
        return (
            z0
            - v_land * t
            - 0.5 * GRAVITY * t * t
            + a * ts / math.pi * (t - ts / math.pi * math.sin(math.pi * t / ts))
        )

    return free(tau) + (z1 - free(ts)) * min_jerk(tau / ts)


GAITS = {
    "run": dict(v_max=2.2, step_time=0.36, stance_time=0.22, z_run=0.70, lean=0.12, apex=0.25, arm=0.5),
    "sprint": dict(v_max=3.5, step_time=0.32, stance_time=0.15, z_run=0.70, lean=0.15, apex=0.25, arm=0.8),
}
"""``_gait`` parameters of the refined run and sprint (footholds +-0.06 m, ``dynamic``); the refined
sprint fails (stance IK out of reach), the shipped sprint is the keyed ``sprint``."""


def refined_plan(style: str, **gait) -> MotionPlan:
    """The refined run or sprint plan (``GAITS``, overridden by ``gait``); ``clipgen.generate`` refines it
    (``run_refine.refine``). Generate and check one: ``python -m rle_tasks.f04_motion_tracking.public.styles
    OUT_DIR run`` then ``rle check-clip OUT_DIR/run.npz``."""
    return _gait(**{**GAITS[style], **gait}, width=0.06, dynamic=True)


def run() -> MotionPlan:
    return refined_plan("run")  # 2.2 m/s, refined by the check's inverse dynamics (issue 42.2)


def sprint() -> MotionPlan:
    return _gait(v_max=3.5, step_time=0.32, stance_time=0.15, z_run=0.70, lean=0.15, apex=0.16, arm=0.8)


STYLES = {"dance": dance, "fight": fight, "fall-getup": fall_getup, "run": run, "sprint": sprint}
"""Style name -> plan factory."""


def plan_for(style: str) -> MotionPlan:
    """The plan of one style (``STYLES``)."""
    return STYLES[style]()


def build_clips(out_dir, styles=None) -> dict[str, Path]:
    """Generate clips (all five, or ``styles``) into ``out_dir/<style>.npz`` (deterministic; about 100 s in
    all on the 2-core machine, mostly balancing and the run's refinement)."""
    from .clipgen import generate
    from .g1 import g1_model

    model = g1_model()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths = {}
    for style in styles or STYLES:
        paths[style] = out / f"{style}.npz"
        generate(model, plan_for(style)).save(paths[style])
    return paths


if __name__ == "__main__":  # python -m rle_tasks.f04_motion_tracking.public.styles OUT_DIR [STYLE ...]
    import sys
    import time

    for style in sys.argv[2:] or STYLES:
        start = time.perf_counter()
        path = build_clips(sys.argv[1], [style])[style]
        print(f"{style} {path} {time.perf_counter() - start:.1f} s")
