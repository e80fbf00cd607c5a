"""Lights and sky of a scene: a gradient skybox, a key light and the viewer's headlight."""

from __future__ import annotations

from dataclasses import dataclass

import mujoco

from rle_design.errors import ConfigError
from rle_design.scene.config import SpecEdit, check_vector

__all__ = ["HeadlightConfig", "LightConfig", "SkyboxConfig"]


def _check_colour(owner: object, field: str, value: tuple[float, ...]) -> None:
    check_vector(owner, field, value, 3)
    if not all(0.0 <= c <= 1.0 for c in value):
        raise ConfigError(f"{type(owner).__name__}.{field} channels must be in [0, 1], got {tuple(value)}")


@dataclass(frozen=True)
class SkyboxConfig(SpecEdit):
    """A vertical gradient skybox texture; a spec that already has a texture of that name keeps it."""

    name: str = "sky"
    """Texture name."""
    top: tuple[float, float, float] = (0.93, 0.95, 0.98)
    """Colour at the zenith (RGB in [0, 1])."""
    bottom: tuple[float, float, float] = (0.62, 0.70, 0.80)
    """Colour at the horizon (RGB in [0, 1])."""
    resolution: int = 64
    """Texture width and height [px]."""

    def validate(self) -> None:
        if not self.name:
            raise ConfigError("SkyboxConfig.name must not be empty")
        _check_colour(self, "top", self.top)
        _check_colour(self, "bottom", self.bottom)
        if self.resolution < 1:
            raise ConfigError(f"SkyboxConfig.resolution must be >= 1, got {self.resolution}")

    def _edit(self, spec: mujoco.MjSpec) -> None:
        if spec.texture(self.name) is not None:
            return
        spec.add_texture(
            name=self.name,
            type=mujoco.mjtTexture.mjTEXTURE_SKYBOX,
            builtin=mujoco.mjtBuiltin.mjBUILTIN_GRADIENT,
            rgb1=list(self.top),
            rgb2=list(self.bottom),
            width=self.resolution,
            height=self.resolution,
        )


@dataclass(frozen=True)
class LightConfig(SpecEdit):
    """A directional key light on the world body, added only when the spec has no light at all."""

    name: str = "key"
    """Light name."""
    pos: tuple[float, float, float] = (1.5, -1.5, 3.0)
    """Position in the world frame [m] (matters for shadows only)."""
    dir: tuple[float, float, float] = (-0.4, 0.4, -1.0)
    """Direction the light points to, world frame (normalised by MuJoCo)."""

    def validate(self) -> None:
        if not self.name:
            raise ConfigError("LightConfig.name must not be empty")
        check_vector(self, "pos", self.pos, 3)
        check_vector(self, "dir", self.dir, 3)
        if not any(self.dir):
            raise ConfigError("LightConfig.dir must not be the zero vector")

    def _edit(self, spec: mujoco.MjSpec) -> None:
        if spec.lights:
            return
        spec.worldbody.add_light(
            name=self.name,
            pos=list(self.pos),
            dir=list(self.dir),
            type=int(mujoco.mjtLightType.mjLIGHT_DIRECTIONAL),
        )


@dataclass(frozen=True)
class HeadlightConfig(SpecEdit):
    """The viewer's headlight (``<visual><headlight>``)."""

    ambient: tuple[float, float, float] = (0.35, 0.35, 0.35)
    """Ambient colour (RGB in [0, 1])."""
    diffuse: tuple[float, float, float] = (0.5, 0.5, 0.5)
    """Diffuse colour (RGB in [0, 1])."""

    def validate(self) -> None:
        _check_colour(self, "ambient", self.ambient)
        _check_colour(self, "diffuse", self.diffuse)

    def _edit(self, spec: mujoco.MjSpec) -> None:
        spec.visual.headlight.ambient = list(self.ambient)
        spec.visual.headlight.diffuse = list(self.diffuse)
