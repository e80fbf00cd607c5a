"""Unitree G1 29-DoF (mjlab 1.6.0 ``g1.xml``, ``g1_29dof_rev_1_0``) PD actuator constants.

The MJCF has no actuators. Each joint gets a position servo whose gains follow mjlab's G1
constants: a motor's reflected inertia through a two-stage planetary gearbox is
``a = J0 (g1 g2)^2 + J1 g2^2 + J2`` [kg m^2]; with natural frequency ``w = 2 pi 10 Hz`` and damping
ratio 2, ``kp = a w^2`` [N m/rad] and ``kd = 2 * 2 * a w`` [N m s/rad]. The ankles and waist
pitch/roll are four-bar linkages driven by two 5020 motors: armature, gains and effort are doubled.
The policy's action scale is ``0.25 effort / kp`` [rad]. Facts from mjlab's ``g1_constants.py``
(rotor inertias and gear ratios are Unitree's motor specifications); no mjlab code is used.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["G1", "G1Constants", "MotorClass", "reflected_inertia"]

NATURAL_FREQ = 2.0 * math.pi * 10.0
"""Closed-loop natural frequency of every joint servo [rad/s]."""
DAMPING_RATIO = 2.0
"""Damping ratio of every joint servo [1]."""


def reflected_inertia(rotor: tuple[float, float, float], gears: tuple[float, float, float]) -> float:
    """Reflected inertia of a two-stage planetary gearbox [kg m^2] (``gears[0]`` is 1)."""
    return rotor[0] * (gears[1] * gears[2]) ** 2 + rotor[1] * gears[2] ** 2 + rotor[2]


@dataclass(frozen=True)
class MotorClass:
    """One actuator class of the G1."""

    name: str
    """Unitree motor type (and ``x2`` for the two-motor linkages)."""
    armature: float
    """Reflected rotor inertia at the joint [kg m^2]."""
    effort: float
    """Symmetric torque limit [N m]."""

    @property
    def kp(self) -> float:
        """Position gain ``a w^2`` [N m/rad]."""
        return self.armature * NATURAL_FREQ**2

    @property
    def kd(self) -> float:
        """Velocity gain ``2 zeta a w`` [N m s/rad]."""
        return 2.0 * DAMPING_RATIO * self.armature * NATURAL_FREQ

    @property
    def action_scale(self) -> float:
        """Policy action scale ``0.25 effort / kp`` [rad]."""
        return 0.25 * self.effort / self.kp


_A5020 = reflected_inertia((0.139e-4, 0.017e-4, 0.169e-4), (1.0, 1.0 + 46.0 / 18.0, 1.0 + 56.0 / 16.0))
_A7520_14 = reflected_inertia((0.489e-4, 0.098e-4, 0.533e-4), (1.0, 4.5, 1.0 + 48.0 / 22.0))
_A7520_22 = reflected_inertia((0.489e-4, 0.109e-4, 0.738e-4), (1.0, 4.5, 5.0))
_A4010 = reflected_inertia((0.068e-4, 0.0, 0.0), (1.0, 5.0, 5.0))

M5020 = MotorClass("5020", _A5020, 25.0)
M7520_14 = MotorClass("7520-14", _A7520_14, 88.0)
M7520_22 = MotorClass("7520-22", _A7520_22, 139.0)
M4010 = MotorClass("4010", _A4010, 5.0)
M5020_X2 = MotorClass("5020x2", 2.0 * _A5020, 50.0)

_LEG = ("hip_pitch", "hip_roll", "hip_yaw", "knee", "ankle_pitch", "ankle_roll")
_ARM = ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow", "wrist_roll", "wrist_pitch", "wrist_yaw")
_MOTOR = {
    "hip_pitch": M7520_14,
    "hip_roll": M7520_22,
    "hip_yaw": M7520_14,
    "knee": M7520_22,
    "ankle_pitch": M5020_X2,
    "ankle_roll": M5020_X2,
    "waist_yaw": M7520_14,
    "waist_roll": M5020_X2,
    "waist_pitch": M5020_X2,
    "shoulder_pitch": M5020,
    "shoulder_roll": M5020,
    "shoulder_yaw": M5020,
    "elbow": M5020,
    "wrist_roll": M5020,
    "wrist_pitch": M4010,
    "wrist_yaw": M4010,
}
# mjlab's KNEES_BENT keyframe (the BeyondMimic default pose); unlisted joints are 0.
_DEFAULT = {
    "hip_pitch": -0.312,
    "knee": 0.669,
    "ankle_pitch": -0.363,
    "elbow": 0.6,
    "shoulder_pitch": 0.2,
    "left_shoulder_roll": 0.2,
    "right_shoulder_roll": -0.2,
}


def _joints() -> tuple[str, ...]:
    legs = tuple(f"{side}_{j}" for side in ("left", "right") for j in _LEG)
    waist = ("waist_yaw", "waist_roll", "waist_pitch")
    arms = tuple(f"{side}_{j}" for side in ("left", "right") for j in _ARM)
    return legs + waist + arms


def _motor(stem: str) -> MotorClass:
    return _MOTOR[stem.removeprefix("left_").removeprefix("right_")]


def _default(stem: str) -> float:
    if stem in _DEFAULT:
        return _DEFAULT[stem]
    return _DEFAULT.get(stem.removeprefix("left_").removeprefix("right_"), 0.0)


@dataclass(frozen=True)
class G1Constants:
    """Joint order, servo constants and default pose of the 29-DoF G1 (MJCF order)."""

    joints: tuple[str, ...]
    """Hinge joint names (``<stem>_joint``), MJCF order."""
    motors: tuple[MotorClass, ...]
    """Actuator class of each joint."""
    default_pose: tuple[float, ...]
    """Default joint positions [rad] (mjlab's knees-bent keyframe)."""
    default_height: float
    """Pelvis height of the default pose standing on the floor [m]."""
    anchor_body: str
    """Body whose pose anchors the reference (BeyondMimic: the torso)."""
    tracked_bodies: tuple[str, ...]
    """The 14 bodies whose positions and orientations are tracked."""
    feet: tuple[str, str]
    """Foot bodies (left, right): stance contacts of the clips."""
    source: str

    @property
    def dof(self) -> int:
        return len(self.joints)

    @property
    def kp(self) -> tuple[float, ...]:
        return tuple(m.kp for m in self.motors)

    @property
    def kd(self) -> tuple[float, ...]:
        return tuple(m.kd for m in self.motors)

    @property
    def effort(self) -> tuple[float, ...]:
        return tuple(m.effort for m in self.motors)

    @property
    def armature(self) -> tuple[float, ...]:
        return tuple(m.armature for m in self.motors)

    @property
    def action_scale(self) -> tuple[float, ...]:
        return tuple(m.action_scale for m in self.motors)


_STEMS = _joints()
G1 = G1Constants(
    joints=tuple(f"{s}_joint" for s in _STEMS),
    motors=tuple(_motor(s) for s in _STEMS),
    default_pose=tuple(_default(s) for s in _STEMS),
    default_height=0.76,
    anchor_body="torso_link",
    tracked_bodies=(
        "pelvis",
        "left_hip_roll_link",
        "left_knee_link",
        "left_ankle_roll_link",
        "right_hip_roll_link",
        "right_knee_link",
        "right_ankle_roll_link",
        "torso_link",
        "left_shoulder_roll_link",
        "left_elbow_link",
        "left_wrist_yaw_link",
        "right_shoulder_roll_link",
        "right_elbow_link",
        "right_wrist_yaw_link",
    ),
    feet=("left_ankle_roll_link", "right_ankle_roll_link"),
    source="mjlab 1.6.0 asset_zoo/robots/unitree_g1 (g1.xml and the G1 constants); BeyondMimic tracked bodies",
)
