"""The ground: an infinite plane at z = 0 (MuJoCo planes collide everywhere; the size is visual)."""

from __future__ import annotations

from dataclasses import dataclass

import mujoco

from rle_design.errors import ConfigError
from rle_design.scene.config import SpecEdit, check_positive, check_vector

__all__ = ["FloorConfig"]


@dataclass(frozen=True)
class FloorConfig(SpecEdit):
    """A ground plane on the world body; a spec that already has a geom of that name keeps its own."""

    name: str = "floor"
    """Geom name."""
    half_size: float = 20.0
    """Half-extent of the drawn plane [m] (collision is unbounded)."""
    grid: float = 0.05
    """Spacing of the rendered grid lines [m] (the plane's third size)."""
    friction: tuple[float, float, float] = (1.0, 0.005, 0.0001)
    """Sliding [1], torsional [m] and rolling [m] friction of the plane."""
    rgba: tuple[float, float, float, float] = (0.82, 0.84, 0.86, 1.0)
    """Colour, each channel in [0, 1]."""

    def validate(self) -> None:
        if not self.name:
            raise ConfigError("FloorConfig.name must not be empty")
        check_positive(self, "half_size", self.half_size)
        check_positive(self, "grid", self.grid)
        check_vector(self, "friction", self.friction, 3)
        if min(self.friction) < 0:
            raise ConfigError(f"FloorConfig.friction must be >= 0, got {tuple(self.friction)}")
        check_vector(self, "rgba", self.rgba, 4)
        if not all(0.0 <= c <= 1.0 for c in self.rgba):
            raise ConfigError(f"FloorConfig.rgba channels must be in [0, 1], got {tuple(self.rgba)}")

    def _edit(self, spec: mujoco.MjSpec) -> None:
        if spec.geom(self.name) is not None:
            return
        spec.worldbody.add_geom(
            name=self.name,
            type=mujoco.mjtGeom.mjGEOM_PLANE,
            size=[self.half_size, self.half_size, self.grid],
            friction=list(self.friction),
            rgba=list(self.rgba),
        )
