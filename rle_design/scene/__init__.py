"""The scene layer: arenas, attachment at sites with name prefixes, spec-edit configs, seeded
variations, named-element lookup and catalog robots with their constants."""

from rle_design.scene.actuators import AdhesionActuator, MotorActuators, PositionActuators
from rle_design.scene.arena import Arena
from rle_design.scene.attach import attach, root_body
from rle_design.scene.camera import CameraConfig, look_at_quat
from rle_design.scene.compose import attach_arm, attach_part, attach_payload, compile_spec, compose
from rle_design.scene.config import SpecEdit
from rle_design.scene.elements import (
    element_id,
    element_ids,
    element_names,
    find_body,
    find_site,
    has_element,
    object_type,
)
from rle_design.scene.floor import FloorConfig
from rle_design.scene.lighting import HeadlightConfig, LightConfig, SkyboxConfig
from rle_design.scene.physics import PhysicsOptions
from rle_design.scene.robots import (
    PANDA,
    TOOL_SITE,
    UR5E,
    XARM7,
    RobotConstants,
    arm_ids,
    arm_model_path,
    load_robot,
    robot_constants,
)
from rle_design.scene.site import SiteConfig
from rle_design.scene.tabletop import ArmPlacement, TabletopConfig, add_free_box, build_tabletop
from rle_design.scene.variation import (
    ComOffset,
    FrictionScale,
    MassScale,
    Perturbation,
    PointMass,
    Uniform,
    Variation,
    VariationSpace,
)
from rle_design.scene.visual import drop_visual_meshes

__all__ = [
    "PANDA",
    "TOOL_SITE",
    "UR5E",
    "XARM7",
    "AdhesionActuator",
    "Arena",
    "ArmPlacement",
    "CameraConfig",
    "ComOffset",
    "FloorConfig",
    "FrictionScale",
    "HeadlightConfig",
    "LightConfig",
    "MassScale",
    "MotorActuators",
    "Perturbation",
    "PhysicsOptions",
    "PointMass",
    "PositionActuators",
    "RobotConstants",
    "SiteConfig",
    "SkyboxConfig",
    "SpecEdit",
    "TabletopConfig",
    "Uniform",
    "Variation",
    "VariationSpace",
    "arm_ids",
    "arm_model_path",
    "add_free_box",
    "attach",
    "attach_arm",
    "drop_visual_meshes",
    "attach_part",
    "attach_payload",
    "build_tabletop",
    "compile_spec",
    "compose",
    "element_id",
    "element_ids",
    "element_names",
    "find_body",
    "find_site",
    "has_element",
    "load_robot",
    "look_at_quat",
    "object_type",
    "robot_constants",
    "root_body",
]
