"""Static and dynamic stability batteries of family 08 (verifier-owned controllers).

Static: for every pose and payload, the static margin (wheel centres as support polygon, COM of the
whole machine) and the force-angle angle must exceed ``STATIC_MARGIN_MIN`` and
``FORCE_ANGLE_MIN_DEG``, and a settled simulation (``SETTLE_S``, arm held by gravity compensation +
PD, wheels braked) must keep every wheel supported (no load below ``LOSS_FRACTION`` m g / 4 for longer than
``LOSS_DURATION_S``) without tilting beyond ``TILT_MAX_DEG``.

Dynamic (2 kg payload): with the arm stowed (transport), base accelerations (equivalent gravity)
forward, backward and sideways, an emergency stop from driving speed and turning in place; with the
arm extended forward and the wheels braked, a fast swing of the first joint. A scenario passes when no wheel stays below ``LOSS_FRACTION`` m g / 4 (loads averaged over 50 ms)
for longer than ``LOSS_DURATION_S`` and the peak tilt stays under ``TILT_MAX_DEG``; the smallest
wheel load is reported. A MuJoCo warning (bad qacc, contact or constraint overflow, NaN) in a static
case or a dynamic scenario fails it, naming the warning (``ScenarioResult.warning``).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.scene import element_id
from rle_design.stability import Scenario, force_angle, run_scenario, static_margin, support_polygon
from rle_tasks.f08_mobile_base.poses import Pose
from rle_tasks.f08_mobile_base.public.scene import STOWED, Scene, hold_torque
from rle_tasks.f08_mobile_base.public.wheels import WHEELS, mecanum_speeds

STATIC_MARGIN_MIN = 0.04  # [m]
FORCE_ANGLE_MIN_DEG = 8.0  # [deg]
SETTLE_S = 0.5  # [s]
LOSS_FRACTION = 0.05  # [1] of m g / 4
LOSS_DURATION_S = 0.25  # [s]
TILT_MAX_DEG = 2.0  # [deg]
ACCEL = 2.5  # nominal base acceleration of the dynamic battery [m/s^2]
DRIVE_SPEED = 1.0  # speed before the emergency stop [m/s]
STOP_DECEL = 2.0  # emergency-stop deceleration ramp of the wheel commands [m/s^2]
TURN_RATE = 1.0  # turning in place [rad/s]
SWING_AMPLITUDE = 0.5  # first-joint swing amplitude [rad]
SWING_FREQ = 0.4  # [Hz]


@dataclass(frozen=True)
class StaticCase:
    """Result of one pose at one payload."""

    pose: str
    payload_kg: int
    margin: float
    force_angle_deg: float
    min_wheel_frac: float
    longest_loss_s: float
    tilt_deg: float
    ik_residual: float
    warning: str | None = None
    """MuJoCo warning raised while settling (the case then fails), or None."""

    @property
    def passed(self) -> bool:
        return (
            self.warning is None
            and self.margin >= STATIC_MARGIN_MIN
            and self.force_angle_deg >= FORCE_ANGLE_MIN_DEG
            and self.longest_loss_s <= LOSS_DURATION_S
            and self.tilt_deg < TILT_MAX_DEG
        )

    @property
    def tips(self) -> bool:
        """The machine cannot stand in this pose (COM outside, or a wheel lifts)."""
        return self.margin <= 0 or self.longest_loss_s > LOSS_DURATION_S or self.tilt_deg >= TILT_MAX_DEG


def _wheel_points(scene: Scene, data: mujoco.MjData) -> np.ndarray:
    ids = [element_id(scene.model, "body", w) for w in WHEELS]
    pts = np.array([data.xpos[i] for i in ids])
    pts[:, 2] -= 0.0762
    return pts


def static_case(scene: Scene, pose: Pose, payload_kg: int, settle_s: float = SETTLE_S) -> StaticCase:
    """Kinematic margins and a settled simulation of ``pose`` (``scene`` carries the payload)."""
    data = scene.rest_data(pose.base_x)
    q = np.array(pose.q)
    data.qpos[scene.chain.qpos_adr] = q
    mujoco.mj_forward(scene.model, data)
    pts = _wheel_points(scene, data)
    com = data.subtree_com[scene.chassis].copy()
    margin = static_margin(support_polygon(pts), com)
    fa = force_angle(pts, com, scene.mass)
    ctrl_idx = scene.arm_act

    def control(model, d, t):
        d.ctrl[ctrl_idx] = hold_torque(scene, d, q)
        d.ctrl[scene.wheel_act] = 0.0

    res = run_scenario(
        scene.model,
        data,
        Scenario("settle", settle_s, control=control, ignore_before=0.1, stop_on_tip=True),
        scene.probe,
    )
    share = res.weight / 4
    return StaticCase(
        pose.name,
        payload_kg,
        margin,
        float(np.degrees(fa.min_theta)),
        res.min_normal / share if res.normal.size else 0.0,
        res.longest_loss,
        res.peak_tilt_deg if not res.tipped else 90.0,
        pose.residual,
        res.warning,
    )


def _extended(scene: Scene, poses: list[Pose]) -> np.ndarray:
    for p in poses:
        if p.name == "reach_front":
            return np.array(p.q)
    return np.array(poses[0].q)


def _stop_profile(t: float, v: float, decel: float) -> float:
    """Fraction of the driving speed commanded at ``t``: ramp up over 0.8 s, cruise, stop ramp at 1.2 s."""
    if t < 1.2:
        return min(1.0, t / 0.8)
    return max(0.0, 1.0 - decel * (t - 1.2) / v)


def dynamic_scenarios(
    scene: Scene, q_ext: np.ndarray, rng: np.random.Generator, quick: bool = False
) -> list[Scenario]:
    """Verifier-owned dynamic scenarios; magnitudes jittered by +-10 % with ``rng``."""
    jit = lambda: float(rng.uniform(0.9, 1.1))  # noqa: E731
    data0 = scene.rest_data()
    q_stow = np.array(STOWED[scene.arm])
    ids = [element_id(scene.model, "body", w) for w in WHEELS]
    wheel_xy = np.array([data0.xpos[i][:2] for i in ids]) - data0.xpos[scene.chassis][:2]

    def hold(d, wheels=None, q=q_ext, qd=None):
        d.ctrl[scene.arm_act] = hold_torque(scene, d, q, qd)
        d.ctrl[scene.wheel_act] = 0.0 if wheels is None else wheels

    def accel_step(direction, a):
        u = np.array(direction, dtype=float)
        return lambda t: u * a * float(np.clip((t - 0.2) / 0.15, 0.0, 1.0))

    out = []
    for name, u in (
        ("accel_forward", (1, 0, 0)),
        ("accel_backward", (-1, 0, 0)),
        ("accel_left", (0, 1, 0)),
        ("accel_right", (0, -1, 0)),
    ):
        if quick and name in ("accel_backward", "accel_right"):
            continue
        out.append(
            Scenario(
                name,
                1.0,
                control=lambda m, d, t: hold(d, q=q_stow),
                accel=accel_step(u, ACCEL * jit()),
                ignore_before=0.15,
            )
        )
    v = DRIVE_SPEED * jit()
    decel = STOP_DECEL * jit()
    drive = mecanum_speeds(v, 0.0, 0.0, wheel_xy)
    out.append(
        Scenario(
            "emergency_stop",
            2.0,
            control=lambda m, d, t: hold(d, drive * _stop_profile(t, v, decel), q=q_stow),
            ignore_before=0.15,
        )
    )
    w = TURN_RATE * jit()
    turn = mecanum_speeds(0.0, 0.0, w, wheel_xy)
    out.append(
        Scenario(
            "turn_in_place",
            2.0,
            control=lambda m, d, t: hold(d, turn * min(1.0, t / 0.5), q=q_stow),
            ignore_before=0.15,
        )
    )
    if not quick:
        amp, f = SWING_AMPLITUDE * jit(), SWING_FREQ * jit()

        def swing(m, d, t):
            q = q_ext.copy()
            qd = np.zeros_like(q)
            s = min(1.0, t / 0.3)
            q[0] += s * amp * np.sin(2 * np.pi * f * t)
            qd[0] = s * amp * 2 * np.pi * f * np.cos(2 * np.pi * f * t)
            hold(d, None, q, qd)

        out.append(Scenario("arm_swing", 2.0, control=swing, ignore_before=0.15))
    return out


def dynamic_battery(
    scene: Scene, poses: list[Pose], rng: np.random.Generator, quick: bool = False
) -> list[dict]:
    """Run the dynamic scenarios; one summary dict per scenario with ``passed``."""
    q_ext = _extended(scene, poses)
    out = []
    for sc in dynamic_scenarios(scene, q_ext, rng, quick):
        data = scene.rest_data()
        data.qpos[scene.chain.qpos_adr] = q_ext if sc.name == "arm_swing" else np.array(STOWED[scene.arm])
        mujoco.mj_forward(scene.model, data)
        res = run_scenario(scene.model, data, sc, scene.probe)
        share = res.weight / 4
        min_frac = res.min_normal / share if res.normal.size else 0.0
        s = {
            "scenario": sc.name,
            "duration_s": float(sc.duration),
            "min_wheel_frac": min_frac,
            "longest_loss_s": res.longest_loss,
            "peak_tilt_deg": 90.0 if res.tipped and res.peak_tilt_deg < TILT_MAX_DEG else res.peak_tilt_deg,
            "warning": res.warning,
        }
        s["passed"] = bool(
            res.warning is None
            and s["longest_loss_s"] <= LOSS_DURATION_S
            and s["peak_tilt_deg"] < TILT_MAX_DEG
        )
        out.append(s)
    return out
