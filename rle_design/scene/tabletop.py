"""A tabletop scene: a table with a known edge, fixed Panda arms with their grippers, three RGB cameras.

Frame: world z up, the table top at ``z = TabletopConfig.top_z``; the table spans
``x in [edge_x - 2 * half_size[0], edge_x]`` and ``y in [-half_size[1], half_size[1]]``, so its
**edge** (the one the cantilever task overhangs) is the line ``x = edge_x`` with outward normal +x.

Robots (``ArmPlacement``) are the catalog Panda (robosuite model, joint-torque motors) with the
robosuite Panda gripper attached at the tool body; every name of arm ``i`` carries its prefix
(``"panda/"`` by default, ``"left/"`` and ``"right/"`` for ``TabletopConfig.two_arms()``). Per arm the
scene adds a mocap body ``<prefix>target`` (no geoms): the operational-space target the controller
(``rle_design.control``) tracks, kept in ``MjData`` so that resets and replays restore it.

Names per arm (``ArmNames``): joints ``<prefix>joint1..7``, motors ``<prefix>torq_j1..7``, gripper
actuators ``<prefix>hand/gripper_finger_joint1/2`` (position, 0..0.04 m per finger), tool site
``<prefix>hand/grip_site`` (between the finger pads), mocap body ``<prefix>target``.

Free bodies are added with ``add_free_box`` (before ``finish``); ``finish`` compiles the scene, puts
the arms at home, the mocap targets at the tool sites and stores everything as keyframe ``initial``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from rle_design.errors import ConfigError
from rle_design.paths import package_dir
from rle_design.scene.arena import Arena
from rle_design.scene.attach import attach
from rle_design.scene.camera import look_at_quat
from rle_design.scene.robots import PANDA, load_robot, robot_constants

__all__ = [
    "ArmNames",
    "ArmPlacement",
    "TabletopConfig",
    "add_free_box",
    "arm_with_gripper",
    "build_tabletop",
    "finish",
    "free_body_names",
]

GRIPPER_MODEL = "models/assets/grippers/panda_gripper.xml"
"""robosuite Panda gripper, relative to the robosuite package."""
STIFF_SOLREF = (0.005, 1.0)
"""Contact time constant [s] and damping ratio of pieces and table: stiffer than MuJoCo's default
(0.02 s) so a block resting near a supporting edge does not sink and roll over it (the time constant
stays above twice the 2 ms step)."""
INITIAL_KEY = "initial"
"""Keyframe ``finish`` writes: arms at home, free bodies where added, targets at the tool sites."""


@dataclass(frozen=True)
class ArmPlacement:
    """Where one Panda stands on the table top.

    Attributes:
        prefix: Name prefix of everything the arm brings (must end with ``/``).
        pos: Base position on the table top (x, y) [m].
        yaw: Base heading about world z [rad]; 0 faces +x (towards the edge).
    """

    prefix: str = "panda/"
    pos: tuple[float, float] = (-0.05, 0.0)
    yaw: float = 0.0


@dataclass(frozen=True)
class ArmNames:
    """Element names of one arm in the compiled scene."""

    prefix: str

    @property
    def joints(self) -> tuple[str, ...]:
        return tuple(self.prefix + j for j in PANDA.joints)

    @property
    def motors(self) -> tuple[str, ...]:
        return tuple(self.prefix + a for a in PANDA.actuators)

    @property
    def fingers(self) -> tuple[str, str]:
        return (self.prefix + "hand/gripper_finger_joint1", self.prefix + "hand/gripper_finger_joint2")

    @property
    def tool_site(self) -> str:
        return self.prefix + "hand/grip_site"

    @property
    def target(self) -> str:
        return self.prefix + "target"

    @property
    def base(self) -> str:
        return self.prefix + "base"


@dataclass(frozen=True)
class TabletopConfig:
    """The tabletop scene.

    Attributes:
        top_z: Height of the table top [m].
        edge_x: x of the table's edge (outward normal +x) [m].
        half_size: Table half extents (x, y) [m].
        thickness: Table slab thickness [m].
        friction: Sliding friction of the table top [1].
        arms: The robots (none: a robot-free scene, e.g. to settle what the robots left behind).
        cameras: Names of the three RGB cameras (front, side, top), aimed at ``look_at``.
        look_at: Point the cameras aim at [m].
        timestep: Physics step [s].
    """

    top_z: float = 0.75
    edge_x: float = 0.45
    half_size: tuple[float, float] = (0.45, 0.6)
    thickness: float = 0.05
    friction: float = 0.8
    arms: tuple[ArmPlacement, ...] = (ArmPlacement(),)
    cameras: tuple[str, str, str] = ("front", "side", "top")
    look_at: tuple[float, float, float] = (0.3, 0.0, 0.8)
    timestep: float = 0.002

    @classmethod
    def two_arms(cls, gap: float = 0.9, **kwargs: object) -> TabletopConfig:
        """Two Pandas facing each other across the table's centre line (``left/`` at -x, ``right/`` at +x)."""
        cx = kwargs.get("edge_x", cls.edge_x) - kwargs.get("half_size", cls.half_size)[0]  # type: ignore[operator,index]
        arms = (
            ArmPlacement("left/", (cx - gap / 2, 0.0), 0.0),
            ArmPlacement("right/", (cx + gap / 2, 0.0), float(np.pi)),
        )
        return cls(arms=arms, **kwargs)  # type: ignore[arg-type]

    def validate(self) -> None:
        prefixes = [a.prefix for a in self.arms]
        if len(set(prefixes)) != len(prefixes) or any(not p.endswith("/") for p in prefixes):
            raise ConfigError(f"TabletopConfig.arms prefixes must be unique and end with '/', got {prefixes}")
        if min(self.half_size) <= 0 or self.thickness <= 0 or self.timestep <= 0:
            raise ConfigError("TabletopConfig half_size, thickness and timestep must be positive")

    @property
    def center_x(self) -> float:
        return self.edge_x - self.half_size[0]


def _absolute_meshes(spec: mujoco.MjSpec, xml_path: Path) -> None:
    base = xml_path.parent / (spec.meshdir or "")
    for mesh in spec.meshes:
        if mesh.file and not Path(mesh.file).is_absolute():
            mesh.file = str((base / mesh.file).resolve())
    spec.meshdir = ""


def arm_with_gripper(arm_id: str = "panda") -> mujoco.MjSpec:
    """A catalog arm (no keyframes) with the robosuite Panda gripper attached at its ``tool_site``
    under the name prefix ``hand/`` (fingers ``hand/finger_joint1/2``, position actuators
    ``hand/gripper_finger_joint1/2``, site ``hand/grip_site`` between the pads); mesh paths are made
    absolute so the spec can be attached anywhere."""
    arm = load_robot(arm_id, keyframes=False)
    _absolute_meshes(arm, robot_constants(arm_id).model_path)
    gripper_path = package_dir("robosuite") / GRIPPER_MODEL
    gripper = mujoco.MjSpec.from_file(str(gripper_path))
    _absolute_meshes(gripper, gripper_path)
    for sensor in list(gripper.sensors):
        gripper.delete(sensor)
    attach(arm, gripper, "tool_site", "hand/")
    return arm


def build_tabletop(config: TabletopConfig = TabletopConfig()) -> mujoco.MjSpec:
    """A fresh ``MjSpec`` of the table, the arms with grippers, cameras and lights (no free bodies yet).

    Raises:
        ConfigError: Invalid ``config``.
    """
    config.validate()
    spec = mujoco.MjSpec()
    spec.modelname = "tabletop"
    Arena().edit_spec(spec)
    spec.option.timestep = config.timestep
    spec.visual.global_.offwidth = 640
    spec.visual.global_.offheight = 480
    world = spec.worldbody
    hx, hy = config.half_size
    world.add_geom(
        name="table",
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=[hx, hy, config.thickness / 2],
        pos=[config.center_x, 0.0, config.top_z - config.thickness / 2],
        friction=[config.friction, 0.005, 0.0001],
        rgba=[0.55, 0.42, 0.3, 1.0],
        solref=list(STIFF_SOLREF),
    )
    for sx in (-1, 1):
        for sy in (-1, 1):
            h = config.top_z - config.thickness
            world.add_geom(
                type=mujoco.mjtGeom.mjGEOM_BOX,
                size=[0.03, 0.03, h / 2],
                pos=[config.center_x + sx * (hx - 0.05), sy * (hy - 0.05), h / 2],
                rgba=[0.3, 0.25, 0.2, 1.0],
                contype=0,
                conaffinity=0,
            )
    for placement in config.arms:
        c, s = np.cos(placement.yaw / 2), np.sin(placement.yaw / 2)
        site = world.add_site(
            name=placement.prefix + "mount",
            pos=[placement.pos[0], placement.pos[1], config.top_z],
            quat=[c, 0.0, 0.0, s],
            group=5,
        )
        attach(spec, arm_with_gripper("panda"), site, placement.prefix)
        target = world.add_body(name=placement.prefix + "target", mocap=True)
        target.add_site(
            name=placement.prefix + "target_site", size=[0.01, 0, 0], rgba=[0, 1, 0, 0.3], group=5
        )
    look = np.array(config.look_at)
    cam_pos = {
        config.cameras[0]: look + np.array([0.9, 0.0, 0.45]),
        config.cameras[1]: look + np.array([0.0, -0.9, 0.3]),
        config.cameras[2]: look + np.array([0.0, 0.0, 1.0]),
    }
    for name, pos in cam_pos.items():
        up = (1.0, 0.0, 0.0) if name == config.cameras[2] else (0.0, 0.0, 1.0)
        world.add_camera(name=name, pos=list(pos), quat=list(look_at_quat(pos, look, up)), fovy=50.0)
    return spec


def add_free_box(
    spec: mujoco.MjSpec,
    name: str,
    half_size: tuple[float, float, float],
    pos: tuple[float, float, float],
    *,
    quat: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0),
    mass: float = 0.1,
    friction: float = 0.8,
    rgba: tuple[float, float, float, float] = (0.8, 0.3, 0.2, 1.0),
    solref: tuple[float, float] = STIFF_SOLREF,
) -> mujoco.MjsBody:
    """A free box body ``name`` with one geom ``name`` (half extents [m], mass [kg], contact ``solref``)."""
    if spec.body(name) is not None:
        raise ConfigError(f"body '{name}' exists already", code="scene.duplicate_body")
    body = spec.worldbody.add_body(name=name, pos=list(pos), quat=list(quat))
    body.add_freejoint(name=name)
    body.add_geom(
        name=name,
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=list(half_size),
        mass=mass,
        friction=[friction, 0.005, 0.0001],
        rgba=list(rgba),
        condim=4,
        solref=list(solref),
    )
    return body


def free_body_names(model: mujoco.MjModel) -> tuple[str, ...]:
    """Names of the bodies with a free joint, in model order."""
    names = []
    for j in range(model.njnt):
        if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE:
            names.append(model.body(model.jnt_bodyid[j]).name)
    return tuple(names)


def finish(spec: mujoco.MjSpec, config: TabletopConfig = TabletopConfig()) -> mujoco.MjSpec:
    """Add keyframe ``initial``: arms at home (grippers open), free bodies as added, targets at the tool sites."""
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_resetData(model, data)
    for placement in config.arms:
        names = ArmNames(placement.prefix)
        for joint, q in zip(names.joints, PANDA.home):
            data.qpos[model.jnt_qposadr[model.joint(joint).id]] = q
        for finger, q in zip(names.fingers, (0.04, -0.04)):
            data.ctrl[model.actuator(finger).id] = q
            data.qpos[model.jnt_qposadr[model.actuator_trnid[model.actuator(finger).id, 0]]] = q
    mujoco.mj_forward(model, data)
    for placement in config.arms:
        names = ArmNames(placement.prefix)
        site = model.site(names.tool_site).id
        mocap = model.body(names.target).mocapid[0]
        data.mocap_pos[mocap] = data.site_xpos[site]
        mujoco.mju_mat2Quat(data.mocap_quat[mocap], data.site_xmat[site])
    spec.add_key(
        name=INITIAL_KEY,
        qpos=data.qpos.tolist(),
        mpos=data.mocap_pos.ravel().tolist(),
        mquat=data.mocap_quat.ravel().tolist(),
        ctrl=data.ctrl.tolist(),
    )
    return spec
