"""Catalog robots as ``MjSpec``: the arm list, each arm's constants, and a fresh spec with a tool site."""

from __future__ import annotations

from pathlib import Path

import mujoco

from rle_design.catalog import load_catalog
from rle_design.errors import ConfigError, MjcfError
from rle_design.scene.elements import find_body
from rle_design.scene.robots.constants import TOOL_SITE, RobotConstants
from rle_design.scene.robots.panda_constants import PANDA
from rle_design.scene.robots.ur5e_constants import UR5E
from rle_design.scene.robots.xarm7_constants import XARM7
from rle_design.scene.site import SiteConfig

__all__ = ["arm_ids", "arm_model_path", "load_robot", "robot_constants"]

_CONSTANTS: dict[str, RobotConstants] = {c.id: c for c in (PANDA, UR5E, XARM7)}


def arm_ids() -> tuple[str, ...]:
    """Ids of the canonical arms, in catalog order (read from the ``arms`` catalog)."""
    return tuple(load_catalog("arms").ids)


def _check_arm(arm_id: str) -> None:
    ids = arm_ids()
    if arm_id not in ids:
        raise MjcfError(f"unknown arm '{arm_id}'. Available arms: {', '.join(ids)}", code="arm.unknown")


def robot_constants(arm_id: str) -> RobotConstants:
    """Constants of a catalog arm.

    Raises:
        MjcfError: The arm is not in the catalog (code ``arm.unknown``; lists the arms).
        ConfigError: The catalog has the arm but no ``<arm>_constants.py`` defines it.
    """
    _check_arm(arm_id)
    if arm_id not in _CONSTANTS:
        raise ConfigError(
            f"arm '{arm_id}' has no constants module. Arms with constants: {', '.join(sorted(_CONSTANTS))}",
            code="arm.no_constants",
        )
    return _CONSTANTS[arm_id]


def arm_model_path(arm_id: str) -> Path:
    """MJCF of a catalog arm (its ``model`` entry, located without importing the asset package)."""
    _check_arm(arm_id)
    return robot_constants(arm_id).model_path


def load_robot(arm_id: str, *, keyframes: bool = True, tool_site: str = TOOL_SITE) -> mujoco.MjSpec:
    """Fresh ``MjSpec`` of a catalog arm with a site on its tool body.

    Args:
        arm_id: Catalog id, one of ``arm_ids()``.
        keyframes: Add the ``home`` and ``stowed`` keyframes of the arm's constants.
        tool_site: Name of the site added at the tool body's origin (kept if the model has it).

    Raises:
        MjcfError: Unknown arm (lists the arms).
        MissingElement: The catalog's tool body is not in the model.
    """
    constants = robot_constants(arm_id)
    spec = mujoco.MjSpec.from_file(str(constants.model_path))
    find_body(spec, constants.tool_body)
    if spec.site(tool_site) is None:
        SiteConfig(name=tool_site, body=constants.tool_body, radius=0.005, group=5).edit_spec(spec)
    if keyframes:
        for name, qpos in constants.keyframes().items():
            spec.add_key(name=name, qpos=list(qpos))
    return spec
