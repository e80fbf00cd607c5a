"""Constants of a canonical robot: joint names, keyframes and actuator settings of its catalog model.

The catalog (``arms`` kind) owns what is measured or sourced (model file, mass, reach, root and tool
bodies); a ``RobotConstants`` adds what a scene needs to pose and drive the model. Each robot has a
``<robot>_constants.py`` module that defines one.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from rle_design.catalog import Arm, load_catalog
from rle_design.errors import ConfigError
from rle_design.paths import resolve_asset

__all__ = ["RobotConstants", "TOOL_SITE"]

TOOL_SITE = "tool_site"
"""Name of the site ``load_robot`` puts at the origin of the tool body."""


@dataclass(frozen=True)
class RobotConstants:
    """Posing and actuation constants of one catalog robot (names as in the unprefixed model)."""

    id: str
    """Catalog id (``arms`` kind)."""
    joints: tuple[str, ...]
    """Arm joint names, base to tool."""
    home: tuple[float, ...]
    """Home posture, one angle per joint [rad]: the ready pose of the vendor's examples."""
    stowed: tuple[float, ...]
    """Stowed posture, one angle per joint [rad]: the model source's initial posture."""
    actuators: tuple[str, ...]
    """Names of the model's joint-torque motors, one per joint in ``joints`` order."""
    torque_limits: tuple[float, ...]
    """Symmetric torque limit of each motor [N m] (the model's ``ctrlrange``)."""
    source: str
    """Where the postures and limits come from."""

    def __post_init__(self) -> None:
        n = len(self.joints)
        for field in ("home", "stowed", "actuators", "torque_limits"):
            if len(getattr(self, field)) != n:
                raise ConfigError(
                    f"RobotConstants '{self.id}': {field} has {len(getattr(self, field))} entries for {n} joints"
                )

    @property
    def dof(self) -> int:
        return len(self.joints)

    @property
    def entry(self) -> Arm:
        """The catalog entry (model, mass, reach, root and tool bodies)."""
        return load_catalog("arms").get(self.id)

    @property
    def model_path(self) -> Path:
        """Absolute path of the model's MJCF (from the catalog entry's ``model``)."""
        return resolve_asset(self.entry.model)

    @property
    def root_body(self) -> str:
        return self.entry.root_body

    @property
    def tool_body(self) -> str:
        return self.entry.tool_body

    def keyframes(self) -> dict[str, tuple[float, ...]]:
        """Named postures [rad]: ``home`` and ``stowed``."""
        return {"home": self.home, "stowed": self.stowed}
