"""Verifier-owned mecanum wheel model installed on the submitted wheel bodies.

Model (anisotropic capsule contact, nv = 6 + 4): a mecanum wheel transmits force at its ground
contact only along its roller's axis s (45 deg to the wheel's forward direction); perpendicular to s
the roller spins freely. Kinematically this is an omni wheel whose axle is s_perp, the ground
direction perpendicular to s. Each submitted wheel body (immutable: catalog mass, inertia, cylinder)
gets a child ``<name>_roller`` body with a hinge about s_perp and a horizontal capsule along s_perp
(radius = wheel radius). MuJoCo orients the capsule-plane contact frame along the capsule axis, so a
``<pair>`` with friction (mu_free, mu) is anisotropic: mu_free along s_perp (free roller), mu along
s (driven). A velocity actuator with gear sqrt(2) makes ``ctrl`` the true wheel speed [rad/s]:
v . s = q_dot' r = (omega / sqrt 2) r, hence v_x = omega r for pure forward motion.

Drive and braking forces therefore act at ground level and the chassis can lift a wheel: tip-over
comes from contact forces. Errors of the model: the visual hub does not spin (its spin inertia is
moved to the roller hinge as armature), rollers are a continuous envelope (no gaps, no 6 % radius
ripple), roller rolling resistance is a small friction mu_free instead of bearing losses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

__all__ = ["WHEELS", "WheelModel", "install_wheels", "mecanum_speeds"]

WHEELS = ("wheel_fl", "wheel_fr", "wheel_rl", "wheel_rr")
# Roller axis s in the chassis frame (X configuration seen from above, rollers forming an "O" on the
# ground contact side): front-left and rear-right share one direction, front-right and rear-left the other.
_S = {
    "wheel_fl": (1.0, -1.0),
    "wheel_fr": (1.0, 1.0),
    "wheel_rl": (1.0, 1.0),
    "wheel_rr": (1.0, -1.0),
}


@dataclass(frozen=True)
class WheelModel:
    """Parameters of the installed wheel model.

    Attributes:
        radius: Wheel radius [m] (catalog).
        mu: Friction along the roller axis (driven direction) [1].
        mu_free: Friction across the roller axis (free roller) [1].
        kv: Velocity-actuator gain [N m s/rad].
        max_torque: Wheel motor torque limit [N m].
        max_speed: Wheel speed command limit [rad/s].
        armature: Spin inertia of wheel and motor reflected to the roller hinge [kg m^2].
        capsule_half_length: Half-length of the contact capsule (roller envelope) [m].
        solref: Contact time constant [s] and damping ratio of the tyre (softer than MuJoCo's 0.02 s
            default, which lets a rigid chassis on four rigid wheels rock between diagonals).
    """

    radius: float = 0.0762
    mu: float = 1.0
    mu_free: float = 0.02
    kv: float = 4.0
    max_torque: float = 12.0
    max_speed: float = 20.0
    armature: float = 0.006
    capsule_half_length: float = 0.015
    solref: tuple[float, float] = (0.04, 1.0)


def _s_dir(name: str) -> np.ndarray:
    s = np.array([*_S[name], 0.0])
    return s / np.linalg.norm(s)


def install_wheels(
    spec: mujoco.MjSpec, params: WheelModel = WheelModel(), floor: str = "floor", prefix: str = ""
) -> list[str]:
    """Add roller hinges, contact capsules, floor pairs and drive actuators to the wheel bodies.

    The wheel bodies must be aligned with the chassis (their frames' x forward, z up), which the
    validity checks enforce; the submitted cylinder becomes visual only.

    Returns:
        Actuator names in the order ``WHEELS``.
    """
    names = []
    for name in WHEELS:
        body = spec.body(prefix + name)
        for g in body.geoms:
            g.contype = 0
            g.conaffinity = 0
        s = _s_dir(name)
        s_perp = np.array([-s[1], s[0], 0.0])
        roller = body.add_body(name=f"{prefix}{name}_roller", pos=[0, 0, 0])
        roller.add_joint(
            name=f"{prefix}{name}_spin",
            type=mujoco.mjtJoint.mjJNT_HINGE,
            axis=s_perp,
            armature=params.armature,
            damping=0.01,
        )
        # capsule along s_perp: fromto through the wheel centre
        h = params.capsule_half_length
        roller.add_geom(
            name=f"{prefix}{name}_contact",
            type=mujoco.mjtGeom.mjGEOM_CAPSULE,
            fromto=np.concatenate([-h * s_perp, h * s_perp]),
            size=[params.radius, 0, 0],
            mass=0.05,
            contype=0,
            conaffinity=0,
            group=3,
            rgba=[0.2, 0.6, 0.2, 0.3],
        )
        spec.add_pair(
            name=f"{prefix}{name}_ground",
            geomname1=f"{prefix}{name}_contact",
            geomname2=floor,
            condim=3,
            friction=[params.mu_free, params.mu, 0.005, 0.0001, 0.0001],
            solref=list(params.solref),
        )
        act = spec.add_actuator(
            name=f"{prefix}{name}_drive",
            target=f"{prefix}{name}_spin",
            trntype=mujoco.mjtTrn.mjTRN_JOINT,
            gear=[math.sqrt(2.0), 0, 0, 0, 0, 0],
            ctrlrange=[-params.max_speed, params.max_speed],
            ctrllimited=1,
            forcerange=[-params.max_torque, params.max_torque],
            forcelimited=1,
        )
        act.set_to_velocity(kv=params.kv)
        names.append(act.name)
    return names


def mecanum_speeds(
    vx: float, vy: float, wz: float, wheel_xy: np.ndarray, radius: float = 0.0762
) -> np.ndarray:
    """Wheel speeds [rad/s] (order ``WHEELS``) for a chassis twist (vx, vy [m/s], wz [rad/s]).

    Args:
        wheel_xy: (4, 2) wheel contact positions in the chassis frame [m].
    """
    out = []
    for name, (px, py) in zip(WHEELS, np.asarray(wheel_xy, dtype=float)):
        s = _s_dir(name)[:2]
        v = np.array([vx - wz * py, vy + wz * px])
        # v . s = (omega / sqrt2) r  ->  omega = sqrt2 (v . s) / r
        out.append(math.sqrt(2.0) * float(v @ s) / radius)
    return np.array(out)
