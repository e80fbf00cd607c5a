"""Scene of the bimanual stand-in for RoboTwin 2.0: a table, two UR5e arms with parallel grippers
side by side behind it (like RoboTwin's dual-arm platform), a head and a front camera, and the
objects of one task.

Frame: world z up, table top at ``TOP_Z``; the arms stand on the table's back edge (x = ``BASE_X``)
at y = +``ARM_Y`` (``left/``) and -``ARM_Y`` (``right/``), facing +x. Each arm is the catalog UR5e
(robosuite model) with its torque motors replaced by position servos (``ARM_KP``, ``ARM_KV``,
gravity compensated as a real arm's controller does) and the robosuite Panda gripper at the tool
flange (two fingers, position servos, 0..0.04 m each).

``SceneLook`` is what the robust track perturbs (table colour and height, light, camera poses,
object tint, clutter); ``CLEAN`` is the open track's scene. Everything is built with ``MjSpec``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import mujoco
import numpy as np

from rle_design.scene.actuators import PositionActuators
from rle_design.scene.arena import Arena
from rle_design.scene.attach import attach
from rle_design.scene.camera import look_at_quat
from rle_design.scene.robots import robot_constants
from rle_design.scene.tabletop import arm_with_gripper

__all__ = [
    "ARMS",
    "CAMERAS",
    "CLEAN",
    "GRIPPER_OPEN",
    "SceneLook",
    "arm_joint_names",
    "build_model",
    "robust_look",
    "finger_joint_names",
]

ARMS = ("left/", "right/")
"""Arm prefixes, in state and action order."""
TOP_Z = 0.75
"""Table top height [m]."""
TABLE_HALF = (0.42, 0.62)
"""Table half extents (x, y) [m]; the table is centred at x = 0."""
BASE_X = -0.36
"""x of both arm bases on the table's back part [m]."""
ARM_Y = 0.30
"""|y| of the arm bases [m]."""
ARM_KP = (2500.0, 2500.0, 1500.0, 400.0, 400.0, 200.0)
"""Joint servo stiffness, shoulder to wrist 3 [N m/rad]."""
ARM_KV = (120.0, 120.0, 70.0, 20.0, 20.0, 8.0)
"""Joint servo damping [N m s/rad]."""
ARM_FORCE = (150.0, 150.0, 150.0, 28.0, 28.0, 28.0)
"""Joint torque limits [N m] (the UR5e's, as in the catalog constants)."""
GRIPPER_OPEN = 0.04
"""Travel of one finger [m]; a gripper command in [0, 1] maps to 0..0.04 m per finger."""
CAMERAS = ("head", "front")
"""The two views a request carries: from above the work area, and facing the arms across the table."""
HEAD_POS = (0.10, 0.0, 1.75)
HEAD_LOOK = (0.12, 0.0, 0.75)
FRONT_POS = (0.80, 0.0, 1.12)
FRONT_LOOK = (0.0, 0.0, 0.84)


@dataclass(frozen=True)
class SceneLook:
    """What a scene looks like beyond its task objects (the robust track's randomisation).

    Attributes:
        table_rgb: Table top colour [0-1].
        table_dz: Table height offset [m] (arms and objects move with the top).
        light_dir: Direction of the key light (normalised on use).
        light_gain: Diffuse intensity of the key light [0-1].
        head_offset: Head camera position offset [m].
        front_offset: Front camera position offset [m].
        tint: Multiplies the task objects' colours [0-1, per channel].
        clutter: Distractor boxes, each (x, y, half size, r, g, b) [m, m, m, 0-1 x 3].
    """

    table_rgb: tuple[float, float, float] = (0.62, 0.52, 0.40)
    table_dz: float = 0.0
    light_dir: tuple[float, float, float] = (0.3, 0.2, -1.0)
    light_gain: float = 0.3
    head_offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    front_offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    tint: tuple[float, float, float] = (1.0, 1.0, 1.0)
    clutter: tuple[tuple[float, ...], ...] = field(default_factory=tuple)


CLEAN = SceneLook()
"""The open track's (and the demonstrations') scene."""


def robust_look(seed: int) -> SceneLook:
    """The perturbed look of a robust-track episode, drawn from its layout ``seed`` (itself drawn from
    the verifier's secret): table colour and height (+-3 cm), key light direction and intensity,
    both cameras moved by up to 3 cm per axis, object colours tinted (each channel x 0.6-1.0), and
    two to four distractor boxes on the table's free front and side strips."""
    rng = np.random.default_rng([int(seed), 0x5EED])
    u = rng.uniform
    clutter = []
    for _ in range(int(rng.integers(2, 5))):
        if rng.random() < 0.5:  # the front strip, beyond the work area
            x, y = u(0.28, 0.37), u(-0.5, 0.5)
        else:  # the side strips, outside both arms' parts
            x, y = u(-0.05, 0.3), rng.choice([-1.0, 1.0]) * u(0.40, 0.52)
        clutter.append((float(x), float(y), float(u(0.012, 0.028)), *map(float, u(0.05, 0.95, 3))))
    return SceneLook(
        table_rgb=tuple(map(float, u(0.15, 0.9, 3))),
        table_dz=float(u(-0.03, 0.03)),
        light_dir=(float(u(-0.6, 0.6)), float(u(-0.6, 0.6)), -1.0),
        light_gain=float(u(0.12, 0.6)),
        head_offset=tuple(map(float, u(-0.03, 0.03, 3))),
        front_offset=tuple(map(float, u(-0.03, 0.03, 3))),
        tint=tuple(map(float, u(0.6, 1.0, 3))),
        clutter=tuple(clutter),
    )


def arm_joint_names(prefix: str) -> tuple[str, ...]:
    return tuple(prefix + j for j in robot_constants("ur5e").joints)


def finger_joint_names(prefix: str) -> tuple[str, str]:
    return (prefix + "hand/finger_joint1", prefix + "hand/finger_joint2")


def _arm() -> mujoco.MjSpec:
    """The catalog UR5e with the Panda gripper, its torque motors replaced by gravity-compensated
    position servos."""
    constants = robot_constants("ur5e")
    arm = arm_with_gripper("ur5e")
    for act in list(arm.actuators):
        if act.name in constants.actuators:
            arm.delete(act)
    for joint, kp, kv, f in zip(constants.joints, ARM_KP, ARM_KV, ARM_FORCE, strict=True):
        PositionActuators((joint,), kp=kp, kv=kv, forcerange=(-f, f)).edit_spec(arm)
    for body in arm.bodies:
        if body.name:
            body.gravcomp = 1.0
    return arm


def _box(body: mujoco.MjsBody, name: str, half, pos, rgba, mass: float | None = None, **kw) -> None:
    g = body.add_geom(
        name=name,
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=list(half),
        pos=list(pos),
        rgba=list(rgba),
        friction=[1.0, 0.005, 0.0001],
        condim=4,
        **kw,
    )
    if mass is not None:
        g.mass = mass


def build_spec(look: SceneLook = CLEAN) -> mujoco.MjSpec:
    """The table, arms, cameras and lights (no task objects yet)."""
    spec = mujoco.MjSpec()
    spec.modelname = "bimanual_standin"
    Arena().edit_spec(spec)
    spec.option.timestep = 0.002
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.noslip_iterations = 0
    spec.visual.global_.offwidth = 256
    spec.visual.global_.offheight = 256
    world = spec.worldbody
    top = TOP_Z + look.table_dz
    hx, hy = TABLE_HALF
    _box(world, "table", (hx, hy, 0.025), (0.0, 0.0, top - 0.025), (*look.table_rgb, 1.0))
    for sx in (-1, 1):
        for sy in (-1, 1):
            h = top - 0.05
            world.add_geom(
                type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.03, 0.03, h / 2],
                pos=[sx * (hx - 0.05), sy * (hy - 0.05), h / 2], rgba=[0.3, 0.25, 0.2, 1.0],
                contype=0, conaffinity=0,
            )  # fmt: skip
    for prefix, y in zip(ARMS, (ARM_Y, -ARM_Y), strict=True):
        site = world.add_site(name=prefix + "mount", pos=[BASE_X, y, top], group=5)
        attach(spec, _arm(), site, prefix)
    d = np.asarray(look.light_dir, float)
    d = d / np.linalg.norm(d)
    g = float(look.light_gain)
    world.add_light(
        name="scene_key", pos=list(-2.0 * d + np.array([0.0, 0.0, top])), dir=list(d),
        diffuse=[g, g, g], specular=[0.2, 0.2, 0.2], type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL, castshadow=0,
    )  # fmt: skip
    for name, pos, look_at, off in (
        ("head", HEAD_POS, HEAD_LOOK, look.head_offset),
        ("front", FRONT_POS, FRONT_LOOK, look.front_offset),
    ):
        p = np.asarray(pos) + np.asarray(off) + np.array([0.0, 0.0, look.table_dz])
        at = np.asarray(look_at) + np.array([0.0, 0.0, look.table_dz])
        up = (1.0, 0.0, 0.0) if name == "head" else (0.0, 0.0, 1.0)  # the head camera looks nearly down
        fovy = 45.0 if name == "head" else 58.0
        world.add_camera(name=name, pos=list(p), quat=list(look_at_quat(p, at, up)), fovy=fovy)
    for k, (x, y, h, r, gg, b) in enumerate(look.clutter):
        body = world.add_body(name=f"clutter{k}", pos=[x, y, top + h])
        body.add_freejoint(name=f"clutter{k}")
        _box(body, f"clutter{k}", (h, h, h), (0, 0, 0), (r, gg, b, 1.0), mass=0.05)
    return spec


def build_model(spec: mujoco.MjSpec) -> mujoco.MjModel:
    return spec.compile()
