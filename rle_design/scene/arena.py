"""The arena: what a composition owns around the robots (floor, sky, lights, physics options)."""

from __future__ import annotations

from dataclasses import dataclass

import mujoco

from rle_design.scene.config import SpecEdit
from rle_design.scene.floor import FloorConfig
from rle_design.scene.lighting import HeadlightConfig, LightConfig, SkyboxConfig
from rle_design.scene.physics import PhysicsOptions

__all__ = ["Arena"]


_PHYSICS = PhysicsOptions()


@dataclass(frozen=True)
class Arena(SpecEdit):
    """Floor, sky, lights and physics options of a scene; a part set to None is left as the spec has it.

    Elements the spec already has (a geom named like the floor, a texture named like the sky, any
    light) are kept, so a design that brings its own floor is not given a second one. The physics
    options are applied last: they overwrite the options of attached children.
    """

    floor: FloorConfig | None = FloorConfig()
    """Ground plane."""
    skybox: SkyboxConfig | None = SkyboxConfig()
    """Sky texture."""
    light: LightConfig | None = LightConfig()
    """Key light (added only to a spec without lights)."""
    headlight: HeadlightConfig | None = HeadlightConfig()
    """Viewer headlight."""
    physics: PhysicsOptions | None = PhysicsOptions()
    """Physics options the composition imposes."""

    @classmethod
    def bare(cls, physics: PhysicsOptions | None = _PHYSICS) -> Arena:
        """No floor, sky or light: only the physics options (None: not even those)."""
        return cls(floor=None, skybox=None, light=None, headlight=None, physics=physics)

    def _parts(self) -> list[SpecEdit]:
        parts = (self.floor, self.skybox, self.light, self.headlight, self.physics)
        return [p for p in parts if p is not None]

    def validate(self) -> None:
        for part in self._parts():
            part.validate()

    def _edit(self, spec: mujoco.MjSpec) -> None:
        for part in self._parts():
            part.edit_spec(spec)
