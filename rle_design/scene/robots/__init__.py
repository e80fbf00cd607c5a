"""Canonical robots from the catalog, with their constants (mjlab ``asset_zoo`` style)."""

from rle_design.scene.robots.constants import TOOL_SITE, RobotConstants
from rle_design.scene.robots.loader import arm_ids, arm_model_path, load_robot, robot_constants
from rle_design.scene.robots.panda_constants import PANDA
from rle_design.scene.robots.ur5e_constants import UR5E
from rle_design.scene.robots.xarm7_constants import XARM7

__all__ = [
    "PANDA",
    "TOOL_SITE",
    "UR5E",
    "XARM7",
    "RobotConstants",
    "arm_ids",
    "arm_model_path",
    "load_robot",
    "robot_constants",
]
