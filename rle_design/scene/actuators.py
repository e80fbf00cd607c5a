"""Actuators added to named joints: position servos (kp, kv) and torque motors.

One actuator per joint, named ``prefix + joint``; ``forcerange`` limits the joint-space output and
``ctrlrange`` the command. Units follow the joint: hinge [rad, N m], slide [m, N].
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco

from rle_design.errors import ConfigError, MissingElement
from rle_design.scene.config import SpecEdit, check_positive, check_range

__all__ = ["AdhesionActuator", "MotorActuators", "PositionActuators"]


def _check_joints(owner: object, joints: tuple[str, ...]) -> None:
    name = type(owner).__name__
    if not joints:
        raise ConfigError(f"{name}.joints must name at least one joint")
    if isinstance(joints, str):
        raise ConfigError(f"{name}.joints must be a tuple of names, got the string '{joints}'")
    dup = sorted({j for j in joints if joints.count(j) > 1})
    if dup:
        raise ConfigError(f"{name}.joints lists {', '.join(dup)} more than once")


def _check_targets(spec: mujoco.MjSpec, joints: tuple[str, ...], prefix: str) -> None:
    """Every joint exists and no actuator has one of the new names (checked before any edit)."""
    for joint in joints:
        if spec.joint(joint) is None:
            raise MissingElement("joint", joint, available=[j.name for j in spec.joints if j.name])
        if spec.actuator(prefix + joint) is not None:
            raise ConfigError(
                f"actuator '{prefix + joint}' already exists; set a prefix", code="scene.duplicate_actuator"
            )


def _add(
    spec: mujoco.MjSpec,
    joint: str,
    name: str,
    ctrlrange: tuple[float, float] | None,
    forcerange: tuple[float, float] | None,
    gear: float = 1.0,
) -> mujoco.MjsActuator:
    act = spec.add_actuator(name=name, target=joint, trntype=mujoco.mjtTrn.mjTRN_JOINT)
    act.gear = [gear, 0, 0, 0, 0, 0]
    if ctrlrange is not None:
        act.ctrlrange = list(ctrlrange)
        act.ctrllimited = 1
    if forcerange is not None:
        act.forcerange = list(forcerange)
        act.forcelimited = 1
    return act


@dataclass(frozen=True)
class PositionActuators(SpecEdit):
    """PD position servos: force = kp (ctrl - q) - kv qdot, clipped to ``forcerange``."""

    joints: tuple[str, ...]
    """Names of the actuated joints."""
    kp: float
    """Position gain [N m/rad] (slide joints: [N/m])."""
    kv: float = 0.0
    """Velocity gain (damping) [N m s/rad] (slide joints: [N s/m])."""
    forcerange: tuple[float, float] | None = None
    """Output limits [N m] (slide: [N]); None: unlimited."""
    ctrlrange: tuple[float, float] | None = None
    """Target limits [rad] (slide: [m]); None: unlimited."""
    prefix: str = ""
    """Actuator name prefix; each actuator is named ``prefix + joint``."""

    def validate(self) -> None:
        _check_joints(self, self.joints)
        check_positive(self, "kp", self.kp)
        check_positive(self, "kv", self.kv, strict=False)
        if self.forcerange is not None:
            check_range(self, "forcerange", self.forcerange)
        if self.ctrlrange is not None:
            check_range(self, "ctrlrange", self.ctrlrange)

    def _edit(self, spec: mujoco.MjSpec) -> None:
        _check_targets(spec, self.joints, self.prefix)
        for joint in self.joints:
            act = _add(spec, joint, self.prefix + joint, self.ctrlrange, self.forcerange)
            act.set_to_position(kp=self.kp, kv=self.kv)


@dataclass(frozen=True)
class MotorActuators(SpecEdit):
    """Direct torque (force) motors: joint effort = gear x ctrl."""

    joints: tuple[str, ...]
    """Names of the actuated joints."""
    gear: float = 1.0
    """Transmission ratio from command to joint effort [1]."""
    ctrlrange: tuple[float, float] | None = None
    """Command limits [N m] before the gear (slide: [N]); None: unlimited."""
    forcerange: tuple[float, float] | None = None
    """Output limits [N m] (slide: [N]); None: unlimited."""
    prefix: str = ""
    """Actuator name prefix; each actuator is named ``prefix + joint``."""

    def validate(self) -> None:
        _check_joints(self, self.joints)
        check_positive(self, "gear", self.gear)
        if self.ctrlrange is not None:
            check_range(self, "ctrlrange", self.ctrlrange)
        if self.forcerange is not None:
            check_range(self, "forcerange", self.forcerange)

    def _edit(self, spec: mujoco.MjSpec) -> None:
        _check_targets(spec, self.joints, self.prefix)
        for joint in self.joints:
            act = _add(spec, joint, self.prefix + joint, self.ctrlrange, self.forcerange, self.gear)
            act.set_to_motor()


@dataclass(frozen=True)
class AdhesionActuator(SpecEdit):
    """A body adhesion actuator (MuJoCo ``<adhesion>``): an electromagnet or suction cup.

    With command ``c`` in [0, 1] the actuator pulls the geoms touching ``body`` towards it with a total
    normal force ``gain x c`` [N], split among its active contacts; nothing is attracted without
    contact. Contacts of the body's geoms must be enabled (``contype``/``conaffinity``).
    """

    name: str
    """Actuator name (must not exist yet)."""
    body: str
    """Body whose contacts adhere."""
    gain: float
    """Total adhesion force at command 1 [N]."""

    def validate(self) -> None:
        if not self.name:
            raise ConfigError("AdhesionActuator.name must not be empty")
        check_positive(self, "gain", self.gain)

    def _edit(self, spec: mujoco.MjSpec) -> None:
        if spec.body(self.body) is None:
            raise MissingElement("body", self.body, available=[b.name for b in spec.bodies if b.name])
        if spec.actuator(self.name) is not None:
            raise ConfigError(f"actuator '{self.name}' already exists", code="scene.duplicate_actuator")
        act = spec.add_actuator(name=self.name, target=self.body, trntype=mujoco.mjtTrn.mjTRN_BODY)
        act.set_to_adhesion(gain=self.gain)
        act.ctrlrange = [0.0, 1.0]
        act.ctrllimited = 1
