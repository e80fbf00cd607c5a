"""A site added to a body: an attachment point, a tool frame or a measurement point."""

from __future__ import annotations

from dataclasses import dataclass

import mujoco

from rle_design.errors import ConfigError
from rle_design.scene.config import SpecEdit, check_positive, check_vector
from rle_design.scene.elements import find_body

__all__ = ["SiteConfig"]


@dataclass(frozen=True)
class SiteConfig(SpecEdit):
    """A sphere site on a body (sites have no mass and do not collide)."""

    name: str
    """Site name (must not exist yet)."""
    body: str = "world"
    """Body that carries the site."""
    pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
    """Position in the body frame [m]."""
    quat: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    """Orientation in the body frame (w, x, y, z)."""
    radius: float = 0.005
    """Drawn radius [m]."""
    group: int = 5
    """Visibility group, 0..5 (5: hidden in the default viewer)."""

    def validate(self) -> None:
        if not self.name:
            raise ConfigError("SiteConfig.name must not be empty")
        check_vector(self, "pos", self.pos, 3)
        check_vector(self, "quat", self.quat, 4)
        if not any(self.quat):
            raise ConfigError("SiteConfig.quat must not be the zero quaternion")
        check_positive(self, "radius", self.radius)
        if not 0 <= self.group <= 5:
            raise ConfigError(f"SiteConfig.group must be in 0..5, got {self.group}")

    def _edit(self, spec: mujoco.MjSpec) -> None:
        body = find_body(spec, self.body)
        if spec.site(self.name) is not None:
            raise ConfigError(f"site '{self.name}' already exists", code="scene.duplicate_site")
        body.add_site(
            name=self.name, pos=list(self.pos), quat=list(self.quat), size=[self.radius] * 3, group=self.group
        )
