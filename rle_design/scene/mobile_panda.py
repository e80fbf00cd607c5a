"""A Panda on a holonomic mobile base with a torso lift, composed from the robosuite wheel's assets.

The base is robosuite's Omron mobile base (``bases/omron_mobile_base.xml``): three joints on its
root body, a forward slide, a side slide and a yaw hinge (in the frame of the site it is attached
at, so the slides move along that frame's axes, not the rotating base's), and a torso slide that
lifts the arm's support 0..0.34 m. The Panda (the catalog model, joint-torque motors) stands on the
support with the robosuite Panda gripper on its tool body, as in robosuite's ``PandaOmron``.

Masses: the asset's visual geoms get no mass and no contacts, its collision geoms the masses of
``BASE_MASSES``. Actuation (``MobilePandaConfig``): the base joints keep the asset's velocity servos (their command
is a joint velocity [m/s, rad/s]); the torso's unlimited motor is replaced by a position servo (the
asset's 1000 N Coulomb friction on the torso slide, which stands in for robosuite's joint-position
controller, is removed). Cameras ``<prefix>agentview_left`` / ``<prefix>agentview_right`` ride on the
base behind the arm, looking forward over it, and the Panda's ``eye_in_hand`` camera on its hand.

Names (``MobilePandaNames``): everything carries the prefix (``"robot/"`` by default).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from rle_design.errors import ConfigError
from rle_design.paths import package_dir
from rle_design.scene.attach import attach
from rle_design.scene.camera import look_at_quat
from rle_design.scene.config import SpecEdit, check_positive, check_vector
from rle_design.scene.robots import PANDA, load_robot, robot_constants

__all__ = ["MobilePandaConfig", "MobilePandaNames", "absolute_meshes", "panda_with_gripper"]

BASE_MODEL = "models/assets/bases/omron_mobile_base.xml"
"""robosuite's Omron mobile base, relative to the robosuite package."""
GRIPPER_MODEL = "models/assets/grippers/panda_gripper.xml"
"""robosuite's Panda gripper, relative to the robosuite package."""
BASE_MASSES = {"fixed_support": 10.0, "support": 8.0, "wheeled_base": 40.0}
"""Mass of the collision geom of each base body [kg] (the asset leaves them to a density of 1000, 240 kg
in all, most of it in visual meshes); about an Omron LD's 60 kg with the column."""
BASE_FRICTION = 20.0
"""Coulomb friction of the base joints [N, N m]; the asset's 250 against its velocity servos' kv = 1000
would hold the base at half the commanded speed."""
TORSO_RANGE = (0.0, 0.34)
"""Travel of the torso slide [m] (the asset's joint range)."""
HIDDEN_GROUP = 3
"""Geom group of the visual meshes when they are not drawn (renderers show groups 0-2)."""


def absolute_meshes(spec: mujoco.MjSpec, xml_path: Path) -> None:
    """Make the mesh and texture files of ``spec`` (loaded from ``xml_path``) absolute paths."""
    base = xml_path.parent / (spec.meshdir or "")
    for mesh in spec.meshes:
        if mesh.file and not Path(mesh.file).is_absolute():
            mesh.file = str((base / mesh.file).resolve())
    tex_base = xml_path.parent / (spec.texturedir or "")
    for tex in spec.textures:
        if tex.file and not Path(tex.file).is_absolute():
            tex.file = str((tex_base / tex.file).resolve())
    spec.meshdir = ""
    spec.texturedir = ""


def panda_with_gripper() -> mujoco.MjSpec:
    """The catalog Panda with the robosuite Panda gripper attached at its tool site (prefix ``hand/``);
    mesh paths absolute, the gripper's force/torque sensors removed."""
    arm = load_robot("panda", keyframes=False)
    absolute_meshes(arm, robot_constants("panda").model_path)
    gripper_path = package_dir("robosuite") / GRIPPER_MODEL
    gripper = mujoco.MjSpec.from_file(str(gripper_path))
    absolute_meshes(gripper, gripper_path)
    for sensor in list(gripper.sensors):
        gripper.delete(sensor)
    attach(arm, gripper, "tool_site", "hand/")
    return arm


@dataclass(frozen=True)
class MobilePandaNames:
    """Element names of the mobile Panda in the compiled scene."""

    prefix: str = "robot/"

    @property
    def base_joints(self) -> tuple[str, str, str]:
        """Forward slide, side slide, yaw hinge (in the mount site's frame)."""
        p = self.prefix
        return (p + "joint_mobile_forward", p + "joint_mobile_side", p + "joint_mobile_yaw")

    @property
    def base_actuators(self) -> tuple[str, str, str]:
        p = self.prefix
        return (p + "actuator_mobile_forward", p + "actuator_mobile_side", p + "actuator_mobile_yaw")

    @property
    def torso_joint(self) -> str:
        return self.prefix + "joint_torso_height"

    @property
    def torso_actuator(self) -> str:
        return self.prefix + "torso"

    @property
    def base_body(self) -> str:
        """The moving base (carries the base joints)."""
        return self.prefix + "base"

    @property
    def arm_prefix(self) -> str:
        return self.prefix + "arm/"

    @property
    def arm_base(self) -> str:
        return self.arm_prefix + "base"

    @property
    def joints(self) -> tuple[str, ...]:
        return tuple(self.arm_prefix + j for j in PANDA.joints)

    @property
    def motors(self) -> tuple[str, ...]:
        return tuple(self.arm_prefix + a for a in PANDA.actuators)

    @property
    def fingers(self) -> tuple[str, str]:
        p = self.arm_prefix + "hand/"
        return (p + "gripper_finger_joint1", p + "gripper_finger_joint2")

    @property
    def finger_pads(self) -> tuple[str, str]:
        """Bodies of the two fingers (contacts with them count as gripping)."""
        p = self.arm_prefix + "hand/"
        return (p + "leftfinger", p + "rightfinger")

    @property
    def tool_site(self) -> str:
        return self.arm_prefix + "hand/grip_site"

    @property
    def cameras(self) -> tuple[str, str, str]:
        """Left and right agent views on the base, eye in hand."""
        return (
            self.prefix + "agentview_left",
            self.prefix + "agentview_right",
            self.arm_prefix + "eye_in_hand",
        )


@dataclass(frozen=True)
class MobilePandaConfig(SpecEdit):
    """Attach a mobile Panda at a site of a scene (``edit_spec``).

    The base velocity servos and their limits are the asset's (forward and side +-1 m/s, yaw
    +-1.5 rad/s, 600 N); everything else is set here.
    """

    site: str
    """Site of the scene that carries the base (its frame: x forward, z up, on the floor)."""
    prefix: str = "robot/"
    """Name prefix of everything the robot brings (must end with ``/``)."""
    arm_offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    """Position of the arm's root on the torso support [m]."""
    torso_kp: float = 100000.0
    """Torso position servo stiffness [N/m] (the lifted 26 kg sag 2.6 mm)."""
    torso_kv: float = 10000.0
    """Torso position servo damping [N s/m]."""
    torso_force: float = 2000.0
    """Torso servo force limit [N] (the lifted mass is about 25 kg)."""
    camera_fovy_deg: float = 60.0
    """Vertical field of view of the two agent views [deg]."""
    visual_meshes: bool = False
    """Draw the assets' detailed visual meshes (about 270k faces: 30 ms per 128 x 128 view on a CPU
    renderer); False moves them to geom group ``HIDDEN_GROUP`` so cameras draw the collision shapes
    (about 20k faces)."""

    def validate(self) -> None:
        if not self.prefix.endswith("/"):
            raise ConfigError(f"MobilePandaConfig.prefix must end with '/', got '{self.prefix}'")
        check_vector(self, "arm_offset", self.arm_offset, 3)
        for field in ("torso_kp", "torso_kv", "torso_force", "camera_fovy_deg"):
            check_positive(self, field, getattr(self, field))

    @property
    def names(self) -> MobilePandaNames:
        return MobilePandaNames(self.prefix)

    def _base_spec(self) -> mujoco.MjSpec:
        path = package_dir("robosuite") / BASE_MODEL
        base = mujoco.MjSpec.from_file(str(path))
        absolute_meshes(base, path)
        for geom in base.geoms:
            visual = geom.contype == 0 and geom.conaffinity == 0
            if visual or geom.group == 1:  # visual copies: no mass, no contacts
                geom.contype, geom.conaffinity, geom.density = 0, 0, 0.0
            else:
                geom.mass = BASE_MASSES[geom.parent.name]
        for joint in ("joint_mobile_forward", "joint_mobile_side", "joint_mobile_yaw"):
            base.joint(joint).frictionloss = BASE_FRICTION
        torso = base.joint("joint_torso_height")
        torso.frictionloss = 0.0
        torso.damping = [50.0, 0.0, 0.0]
        base.delete(base.actuator("actuator_torso_height"))
        act = base.add_actuator(name="torso", target="joint_torso_height", trntype=mujoco.mjtTrn.mjTRN_JOINT)
        act.set_to_position(kp=self.torso_kp, kv=self.torso_kv)
        act.ctrlrange = list(TORSO_RANGE)
        act.ctrllimited = 1
        act.forcerange = [-self.torso_force, self.torso_force]
        act.forcelimited = 1
        support = base.body("support")
        mount = support.add_site(name="arm_mount", pos=list(self.arm_offset), group=5)
        attach(base, panda_with_gripper(), mount, "arm/", body=PANDA.root_body)
        body = base.body("base")
        for side, y in (("left", 0.35), ("right", -0.35)):
            pos = np.array([-0.5, y, 1.75])
            look = np.array([0.8, 0.0, 0.85])
            body.add_camera(
                name=f"agentview_{side}",
                pos=list(pos),
                quat=list(look_at_quat(pos, look)),
                fovy=self.camera_fovy_deg,
            )
        return base

    def _edit(self, spec: mujoco.MjSpec) -> None:
        site = spec.site(self.site)
        if site is None:
            from rle_design.errors import MissingElement

            raise MissingElement("site", self.site, available=[s.name for s in spec.sites])
        attach(spec, self._base_spec(), site, self.prefix, body="base")
        if not self.visual_meshes:
            for geom in spec.geoms:
                ours = geom.name.startswith(self.prefix) or geom.parent.name.startswith(self.prefix)
                inert = geom.contype == 0 and geom.conaffinity == 0
                if ours and inert and geom.type == mujoco.mjtGeom.mjGEOM_MESH:
                    geom.group = HIDDEN_GROUP
